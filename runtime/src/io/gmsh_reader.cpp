// Gmsh .msh reader: formats 2.2 and 4.1, ASCII and binary.
// Sections read: $MeshFormat, $PhysicalNames, $Entities (4.1), $Nodes,
// $Elements; every other section is skipped. Each count is checked against
// the bytes left in the file before anything is allocated for it.
#include <array>
#include <climits>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "io/mesh_readers.hpp"
#include "mesh/mesh_builder.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass::detail {

namespace {

/// Gmsh element types (Gmsh manual, "MSH file format"): enough to name and
/// skip any common type; only some are supported.
struct GmshType {
  int id;
  const char* description;
  int dim;
  int nodes;
};

constexpr GmshType kGmshTypes[] = {
    {1, "2-node line", 1, 2},           {2, "3-node triangle", 2, 3},       {3, "4-node quadrangle", 2, 4},
    {4, "4-node tetrahedron", 3, 4},    {5, "8-node hexahedron", 3, 8},     {6, "6-node prism", 3, 6},
    {7, "5-node pyramid", 3, 5},        {8, "3-node line", 1, 3},           {9, "6-node triangle", 2, 6},
    {10, "9-node quadrangle", 2, 9},    {11, "10-node tetrahedron", 3, 10}, {12, "27-node hexahedron", 3, 27},
    {13, "18-node prism", 3, 18},       {14, "14-node pyramid", 3, 14},     {15, "1-node point", 0, 1},
    {16, "8-node quadrangle", 2, 8},    {17, "20-node hexahedron", 3, 20},  {18, "15-node prism", 3, 15},
    {19, "13-node pyramid", 3, 13},     {20, "9-node triangle", 2, 9},      {21, "10-node triangle", 2, 10},
    {22, "12-node triangle", 2, 12},    {23, "15-node triangle", 2, 15},    {24, "15-node triangle", 2, 15},
    {25, "21-node triangle", 2, 21},    {26, "4-node line", 1, 4},          {27, "5-node line", 1, 5},
    {28, "6-node line", 1, 6},          {29, "20-node tetrahedron", 3, 20}, {30, "35-node tetrahedron", 3, 35},
    {31, "56-node tetrahedron", 3, 56}, {92, "64-node hexahedron", 3, 64},  {93, "125-node hexahedron", 3, 125},
};

const GmshType* find_gmsh_type(long id) {
  for (const GmshType& type : kGmshTypes)
    if (type.id == id) return &type;
  return nullptr;
}

/// How a supported Gmsh type maps to ours: the shape and order[k] = our
/// index of the k-th Gmsh node (nullptr: same order).
struct Mapping {
  const Shape* shape = nullptr;
  const int* order = nullptr;
};

Mapping find_mapping(long gmsh_id) {
  if (gmsh_id == 15) return {find_shape("point"), nullptr};
  if (gmsh_id == 1) return {find_shape("line2"), nullptr};
  if (gmsh_id == 8) return {find_shape("line3"), nullptr};
  for (const tm_element_info* element : Registry::instance().elements())
    if (element->gmsh_type == gmsh_id) return {shape_of(element), element->gmsh_order};
  return {};
}

std::string supported_list() {
  std::string text = "point (15), line2 (1), line3 (8)";
  for (const tm_element_info* element : Registry::instance().elements())
    text += std::string(", ") + element->name + " (" + std::to_string(element->gmsh_type) + ")";
  return text;
}

long group_key(int dim, long tag) { return (static_cast<long>(dim) << 32) | (tag & 0xffffffffL); }

/// Gmsh tags of physical groups are ints: a larger one cannot be a group.
bool is_physical_tag(long tag) { return tag >= -static_cast<long>(INT_MAX) && tag <= INT_MAX; }

class GmshReader {
 public:
  explicit GmshReader(InputCursor& input) : in_(input), builder_(input.path(), "element") {}
  Mesh read();

 private:
  void read_format();
  void read_physical_names();
  void read_entities();
  void read_entities_ascii();
  void read_entities_binary();
  void read_nodes_22();
  void read_nodes_41();
  void read_node_block_41(long count, int entity_dim, bool parametric);
  void read_elements_22();
  void read_elements_22_binary(long total);
  void read_elements_41();
  Mapping mapping_for(long type_id, Location where) const;
  void add_element(const GmshType& type, long id, std::span<const long> file_nodes, std::span<const long> groups,
                   Location where);
  GroupInfo describe(long key) const;

  int binary_int(std::string_view what) { return in_.value<std::int32_t>(what, order_); }
  double binary_double(std::string_view what) { return in_.value<double>(what, order_); }
  long binary_size(std::string_view what, std::size_t min_bytes_each);
  long binary_tag(std::string_view what);
  double coordinate(std::string_view what) { return binary_ ? binary_double(what) : in_.real(what); }

  InputCursor& in_;
  MeshBuilder builder_;
  int major_ = 0;
  bool binary_ = false;
  std::endian order_ = std::endian::little;
  bool have_nodes_ = false;
  bool have_elements_ = false;
  std::map<std::pair<int, long>, std::string> names_;
  std::map<std::pair<int, long>, std::vector<long>> entity_groups_;
  std::vector<long> ours_;
  std::size_t group_memberships_ = 0;  ///< elements times their groups, over the 4.1 element blocks
};

Mesh GmshReader::read() {
  if (in_.peek_token() != "$MeshFormat") in_.fail("not a Gmsh .msh file: expected $MeshFormat");
  while (!in_.at_end()) {
    const std::string_view token = in_.token("a section");
    if (token.size() < 2 || token.front() != '$')
      in_.fail("expected a section name such as $Nodes, found '" + std::string(token.substr(0, 40)) + "'");
    const std::string name(token.substr(1));
    if (name == "MeshFormat") read_format();
    else if (name == "PhysicalNames") read_physical_names();
    else if (name == "Entities" && major_ == 4) read_entities();
    else if (name == "Nodes") major_ == 4 ? read_nodes_41() : read_nodes_22();
    else if (name == "Elements") major_ == 4 ? read_elements_41() : read_elements_22();
    else if (name == "PartitionedEntities") in_.fail("partitioned meshes are not supported");
    else in_.skip_past("$End" + name, "$End" + name);
  }
  if (!have_nodes_) throw InputError(in_.path() + ": no $Nodes section");
  if (!have_elements_) throw InputError(in_.path() + ": no $Elements section");
  in_.release();  // the text is parsed: the mesh is built without it (36 MB at a million tets)
  return builder_.build([this](long key) { return describe(key); });
}

void GmshReader::read_format() {
  const Location where = in_.here();
  const std::string version(in_.token("the format version"));
  if (version == "4.1") major_ = 4;
  else if (version.size() >= 2 && version.substr(0, 2) == "2.") major_ = 2;
  else in_.fail_at(where, "MSH format " + version + " is not supported (2.2 or 4.1; re-save the mesh with Gmsh)");
  const long file_type = in_.integer("the file type");
  if (file_type != 0 && file_type != 1)
    in_.fail("file type must be 0 (ASCII) or 1 (binary), found " + std::to_string(file_type));
  const long data_size = in_.integer("the data size");
  if (data_size != 8) in_.fail("data size " + std::to_string(data_size) + " is not supported (8)");
  binary_ = file_type == 1;
  if (binary_) {
    in_.skip_line_end();
    in_.set_binary(true);
    const Location marker = in_.location();
    const std::int32_t one = in_.value<std::int32_t>("the endianness marker", std::endian::little);
    if (one == 1) order_ = std::endian::little;
    else if (one == 0x01000000) order_ = std::endian::big;
    else in_.fail_at(marker, "bad endianness marker " + std::to_string(one) + " (expected the integer 1)");
  }
  in_.expect("$EndMeshFormat");
}

void GmshReader::read_physical_names() {
  const long count = in_.count("physical names", 6);
  for (long i = 0; i < count; ++i) {
    const Location where = in_.here();
    const int dim = static_cast<int>(in_.integer("a physical dimension"));
    const long tag = in_.integer("a physical tag");
    std::string_view name = in_.rest_of_line();
    if (name.size() < 2 || name.front() != '"' || name.back() != '"')
      in_.fail_at(where, "physical name must be a quoted string, found '" + std::string(name.substr(0, 40)) + "'");
    names_[{dim, tag}] = std::string(name.substr(1, name.size() - 2));
  }
  in_.expect("$EndPhysicalNames");
}

long GmshReader::binary_size(std::string_view what, std::size_t min_bytes_each) {
  const Location where = in_.here();
  const auto n = in_.value<std::uint64_t>(what, order_);
  return in_.checked_count(n, what, min_bytes_each, where);
}

long GmshReader::binary_tag(std::string_view what) {
  const Location where = in_.here();
  const auto tag = in_.value<std::uint64_t>(what, order_);
  if (tag > static_cast<std::uint64_t>(LONG_MAX))
    in_.fail_at(where, std::string(what) + " " + std::to_string(tag) + " is too large");
  return static_cast<long>(tag);
}

void GmshReader::read_entities() {
  if (binary_) {
    in_.skip_line_end();
    read_entities_binary();
  } else {
    read_entities_ascii();
  }
  in_.expect("$EndEntities");
}

void GmshReader::read_entities_ascii() {
  std::array<long, 4> counts{};
  for (long& n : counts) n = in_.count("entities", 8);
  for (int dim = 0; dim < 4; ++dim)
    for (long i = 0; i < counts[dim]; ++i) {
      const long tag = in_.integer("an entity tag");
      for (int c = 0; c < (dim == 0 ? 3 : 6); ++c) in_.real("an entity bounding box");
      const long physicals = in_.count("physical tags", 2);
      std::vector<long>& groups = entity_groups_[{dim, tag}];
      for (long p = 0; p < physicals; ++p) {
        const long physical = in_.integer("a physical tag");
        if (!is_physical_tag(physical)) in_.fail("physical tag " + std::to_string(physical) + " is not an int");
        groups.push_back(std::abs(physical));
      }
      if (dim == 0) continue;
      const long bounding = in_.count("bounding entities", 2);
      for (long b = 0; b < bounding; ++b) in_.integer("a bounding entity tag");
    }
}

void GmshReader::read_entities_binary() {
  std::array<long, 4> counts{};
  for (long& n : counts) n = binary_size("entities", 28);
  for (int dim = 0; dim < 4; ++dim)
    for (long i = 0; i < counts[dim]; ++i) {
      const long tag = binary_int("an entity tag");
      for (int c = 0; c < (dim == 0 ? 3 : 6); ++c) binary_double("an entity bounding box");
      const long physicals = binary_size("physical tags", 4);
      std::vector<long>& groups = entity_groups_[{dim, tag}];
      for (long p = 0; p < physicals; ++p) groups.push_back(std::abs(static_cast<long>(binary_int("a physical tag"))));
      if (dim == 0) continue;
      const long bounding = binary_size("bounding entities", 4);
      in_.bytes(4 * static_cast<std::size_t>(bounding), "bounding entity tags");
    }
}

void GmshReader::read_nodes_22() {
  const long count = in_.count("nodes", binary_ ? 28 : 8);
  builder_.reserve_nodes(static_cast<std::size_t>(count));
  if (binary_) in_.skip_line_end();
  for (long i = 0; i < count; ++i) {
    const Location where = in_.here();
    const long id = binary_ ? binary_int("a node id") : in_.integer("a node id");
    double xyz[3];
    for (double& x : xyz) x = coordinate("a node coordinate");
    builder_.add_node(id, xyz, where);
  }
  in_.expect("$EndNodes");
  have_nodes_ = true;
}

void GmshReader::read_nodes_41() {
  long blocks = 0;
  if (binary_) {
    in_.skip_line_end();
    blocks = binary_size("node blocks", 20);
    builder_.reserve_nodes(static_cast<std::size_t>(binary_size("nodes", 32)));
    in_.bytes(16, "the node tag range");
  } else {
    blocks = in_.count("node blocks", 8);
    builder_.reserve_nodes(static_cast<std::size_t>(in_.count("nodes", 8)));
    in_.integer("the minimum node tag");
    in_.integer("the maximum node tag");
  }
  for (long b = 0; b < blocks; ++b) {
    const int entity_dim =
        binary_ ? binary_int("an entity dimension") : static_cast<int>(in_.integer("an entity dimension"));
    if (binary_) binary_int("an entity tag");
    else in_.integer("an entity tag");
    const long parametric = binary_ ? binary_int("the parametric flag") : in_.integer("the parametric flag");
    const long count = binary_ ? binary_size("nodes in the block", 32) : in_.count("nodes in the block", 8);
    if (entity_dim < 0 || entity_dim > 3) in_.fail("entity dimension " + std::to_string(entity_dim) + " is not 0..3");
    read_node_block_41(count, entity_dim, parametric != 0);
  }
  in_.expect("$EndNodes");
  have_nodes_ = true;
}

void GmshReader::read_node_block_41(long count, int entity_dim, bool parametric) {
  std::vector<long> tags(static_cast<std::size_t>(count));
  for (long& tag : tags) {
    tag = binary_ ? binary_tag("a node tag") : in_.integer("a node tag");
  }
  const int extra = parametric ? entity_dim : 0;
  for (long tag : tags) {
    const Location where = in_.here();
    double xyz[3];
    for (double& x : xyz) x = coordinate("a node coordinate");
    for (int p = 0; p < extra; ++p) coordinate("a parametric coordinate");
    builder_.add_node(tag, xyz, where);
  }
}

Mapping GmshReader::mapping_for(long type_id, Location where) const {
  const GmshType* type = find_gmsh_type(type_id);
  if (!type) in_.fail_at(where, "unknown Gmsh element type " + std::to_string(type_id));
  const Mapping mapping = find_mapping(type_id);
  if (!mapping.shape)
    in_.fail_at(where, "Gmsh element type " + std::to_string(type_id) + " (" + type->description +
                           ") is not supported; supported types: " + supported_list());
  return mapping;
}

void GmshReader::add_element(const GmshType& type, long id, std::span<const long> file_nodes,
                             std::span<const long> groups, Location where) {
  const Mapping mapping = mapping_for(type.id, where);
  ours_.assign(file_nodes.begin(), file_nodes.end());
  if (mapping.order)
    for (std::size_t k = 0; k < file_nodes.size(); ++k)
      ours_[static_cast<std::size_t>(mapping.order[k])] = file_nodes[k];
  builder_.add_element(*mapping.shape, id, ours_, groups, where);
}

void GmshReader::read_elements_22() {
  const long count = in_.count("elements", binary_ ? 12 : 8);
  builder_.reserve_elements(static_cast<std::size_t>(count));
  if (binary_) {
    in_.skip_line_end();
    read_elements_22_binary(count);
  } else {
    std::vector<long> nodes;
    for (long i = 0; i < count; ++i) {
      const Location where = in_.here();
      const long id = in_.integer("an element id");
      const long type_id = in_.integer("an element type");
      const GmshType* type = find_gmsh_type(type_id);
      mapping_for(type_id, where);
      const long tags = in_.count("element tags", 2);
      long physical = 0;
      for (long t = 0; t < tags; ++t) {
        const long tag = in_.integer("an element tag");
        if (t == 0) physical = tag;
      }
      if (!is_physical_tag(physical)) in_.fail_at(where, "physical tag " + std::to_string(physical) + " is not an int");
      nodes.resize(static_cast<std::size_t>(type->nodes));
      for (long& node : nodes) node = in_.integer("a node id");
      const long group = group_key(type->dim, physical);
      add_element(*type, id, nodes, physical != 0 ? std::span<const long>(&group, 1) : std::span<const long>(), where);
    }
  }
  in_.expect("$EndElements");
  have_elements_ = true;
}

void GmshReader::read_elements_22_binary(long total) {
  std::vector<long> nodes;
  long done = 0;
  while (done < total) {
    const Location where = in_.here();
    const long type_id = binary_int("an element type");
    const GmshType* type = find_gmsh_type(type_id);
    mapping_for(type_id, where);
    const long count = binary_int("an element count");
    const long tags = binary_int("a tag count");
    if (count <= 0 || count > total - done)
      in_.fail_at(where, "element block of " + std::to_string(count) + " elements, but " +
                             std::to_string(total - done) + " remain of the declared " + std::to_string(total));
    if (tags < 0 || tags > 1000) in_.fail_at(where, "bad tag count " + std::to_string(tags));
    in_.checked_count(static_cast<unsigned long long>(count), "elements",
                      4 * static_cast<std::size_t>(1 + tags + type->nodes), where);
    nodes.resize(static_cast<std::size_t>(type->nodes));
    for (long i = 0; i < count; ++i) {
      const Location element_where = in_.here();
      const long id = binary_int("an element id");
      long physical = 0;
      for (long t = 0; t < tags; ++t) {
        const long tag = binary_int("an element tag");
        if (t == 0) physical = tag;
      }
      for (long& node : nodes) node = binary_int("a node id");
      const long group = group_key(type->dim, physical);
      add_element(*type, id, nodes, physical != 0 ? std::span<const long>(&group, 1) : std::span<const long>(),
                  element_where);
    }
    done += count;
  }
}

void GmshReader::read_elements_41() {
  long blocks = 0;
  if (binary_) {
    in_.skip_line_end();
    blocks = binary_size("element blocks", 20);
    builder_.reserve_elements(static_cast<std::size_t>(binary_size("elements", 16)));
    in_.bytes(16, "the element tag range");
  } else {
    blocks = in_.count("element blocks", 8);
    builder_.reserve_elements(static_cast<std::size_t>(in_.count("elements", 4)));
    in_.integer("the minimum element tag");
    in_.integer("the maximum element tag");
  }
  std::vector<long> nodes;
  for (long b = 0; b < blocks; ++b) {
    const Location where = in_.here();
    const int entity_dim =
        binary_ ? binary_int("an entity dimension") : static_cast<int>(in_.integer("an entity dimension"));
    const long entity = binary_ ? binary_int("an entity tag") : in_.integer("an entity tag");
    const long type_id = binary_ ? binary_int("an element type") : in_.integer("an element type");
    const GmshType* type = find_gmsh_type(type_id);
    mapping_for(type_id, where);
    const std::size_t bytes_each = (binary_ ? 8 : 2) * static_cast<std::size_t>(1 + type->nodes);
    const long count =
        binary_ ? binary_size("elements in the block", bytes_each) : in_.count("elements in the block", bytes_each);
    if (entity_dim < 0 || entity_dim > 3)
      in_.fail_at(where, "entity dimension " + std::to_string(entity_dim) + " is not 0..3");
    std::vector<long> groups;
    if (const auto found = entity_groups_.find({entity_dim, entity}); found != entity_groups_.end())
      for (long tag : found->second) groups.push_back(group_key(entity_dim, tag));
    // Each element of the block is stored with every group of its entity:
    // an entity of many physical tags times a block of many elements would
    // take memory without bound, so the memberships stay within one per byte.
    group_memberships_ += groups.size() * static_cast<std::size_t>(count);
    if (group_memberships_ > in_.data().size())
      in_.fail_at(where, "the element blocks put elements into " + std::to_string(group_memberships_) +
                             " physical groups in all, more than the file's " + std::to_string(in_.data().size()) +
                             " bytes can describe (bad physical tag lists in $Entities?)");
    nodes.resize(static_cast<std::size_t>(type->nodes));
    for (long i = 0; i < count; ++i) {
      const Location element_where = in_.here();
      const long id = binary_ ? binary_tag("an element tag") : in_.integer("an element tag");
      for (long& node : nodes) node = binary_ ? binary_tag("a node tag") : in_.integer("a node tag");
      add_element(*type, id, nodes, groups, element_where);
    }
  }
  in_.expect("$EndElements");
  have_elements_ = true;
}

GroupInfo GmshReader::describe(long key) const {
  const int dim = static_cast<int>(key >> 32);
  const long tag = key & 0xffffffffL;
  const auto found = names_.find({dim, tag});
  return {found != names_.end() ? found->second : std::to_string(tag), dim};
}

}  // namespace

Mesh read_gmsh(InputCursor& input) { return GmshReader(input).read(); }

}  // namespace tensormass::detail
