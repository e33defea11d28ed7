// Gmsh .msh writer (ASCII 4.1 and 2.2). The mesh is first flattened into a
// list of Gmsh elements (cells, group facets, group points) with their
// physical tags and entities; the two formats are two printers of that list.
#include "tensormass/io/gmsh_writer.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include "tensormass/common/errors.hpp"
#include "tensormass/io/atomic_file.hpp"
#include "tensormass/mesh/mesh_topology.hpp"

namespace tensormass::io {
namespace {

constexpr int kGmshPoint = 15;

/// One Gmsh element: type, 0-based nodes in Gmsh order, physical tags, entity.
struct MshElement {
  int type = 0;
  int dim = 0;
  std::vector<int> nodes;
  std::vector<int> physical;  ///< ascending
  int entity = 0;             ///< entity tag within dimension `dim`
};

struct Entity {
  int dim = 0;
  int tag = 0;
  std::vector<int> physical;
  std::array<double, 6> box{};  ///< min x, y, z, max x, y, z
};

/// Everything both formats print.
struct MshModel {
  std::vector<MshElement> elements;       ///< element tag = index + 1
  std::vector<Entity> entities;           ///< in order of creation, tags per dimension from 1
  std::vector<std::array<int, 2>> names;  ///< (dim, group index), sorted
};

int physical_tag(std::size_t group) { return static_cast<int>(group) + 1; }

/// Gmsh type of a facet with `count` nodes, corners first then mid-edge nodes.
/// A group facet as a Gmsh element: line2 (type 1) or line3 (8) in a 2D
/// mesh, the registry's 2D element with its node count in a 3D one (nodes
/// put in Gmsh's order).
MshElement facet_element_of(const std::vector<int>& nodes, int mesh_dim) {
  const int count = static_cast<int>(nodes.size());
  if (mesh_dim == 2) {
    if (count != 2 && count != 3)
      throw std::invalid_argument("msh: no Gmsh line type with " + std::to_string(count) + " nodes");
    return {count == 2 ? 1 : 8, 1, nodes, {}, 0};
  }
  const tm_element_info* element = facet_element(count);
  if (!element) throw std::invalid_argument("msh: no 2D element of " + std::to_string(count) + " nodes for a facet");
  MshElement out{element->gmsh_type, 2, {}, {}, 0};
  for (int k = 0; k < count; ++k) out.nodes.push_back(nodes[element->gmsh_order[k]]);
  return out;
}

void add_cells(const Mesh& mesh, MshModel& model) {
  std::vector<std::vector<int>> physical(mesh.cell_count());
  for (std::size_t g = 0; g < mesh.groups.size(); ++g)
    for (int cell : mesh.groups[g].cells) physical[cell].push_back(physical_tag(g));
  for (const ElementBlock& block : mesh.blocks) {
    const tm_element_info& element = *block.element;
    for (int local = 0; local < block.count(); ++local) {
      MshElement out{element.gmsh_type, mesh.dim, {}, physical[block.first_cell + local], 0};
      const std::span<const int> nodes = block.cell_nodes(local);
      for (int k = 0; k < element.nodes; ++k) out.nodes.push_back(nodes[element.gmsh_order[k]]);
      model.elements.push_back(std::move(out));
    }
  }
}

/// Group facets, each distinct facet (by node set) once, with all its groups' tags.
void add_facets(const Mesh& mesh, MshModel& model) {
  std::map<std::vector<int>, std::size_t> seen;
  for (std::size_t g = 0; g < mesh.groups.size(); ++g) {
    const FacetSet& facets = mesh.groups[g].facets;
    for (int f = 0; f < facets.count(); ++f) {
      std::vector<int> nodes(facets.nodes.begin() + facets.offsets[f], facets.nodes.begin() + facets.offsets[f + 1]);
      std::vector<int> key = nodes;
      std::sort(key.begin(), key.end());
      const auto [where, inserted] = seen.emplace(key, model.elements.size());
      if (inserted) model.elements.push_back(facet_element_of(nodes, mesh.dim));
      std::vector<int>& tags = model.elements[where->second].physical;
      if (tags.empty() || tags.back() != physical_tag(g)) tags.push_back(physical_tag(g));
    }
  }
}

/// Group nodes that none of the group's cells or facets carry, as point elements.
void add_points(const Mesh& mesh, MshModel& model) {
  std::map<int, std::size_t> point_of_node;
  for (std::size_t g = 0; g < mesh.groups.size(); ++g) {
    const Group& group = mesh.groups[g];
    std::vector<char> covered(mesh.node_count(), 0);
    for (int cell : group.cells) {
      const auto [b, local] = mesh.locate(cell);
      for (int node : mesh.blocks[b].cell_nodes(local)) covered[node] = 1;
    }
    for (int node : group.facets.nodes) covered[node] = 1;
    for (int node : group.nodes) {
      if (covered[node]) continue;
      const auto [where, inserted] = point_of_node.emplace(node, model.elements.size());
      if (inserted) model.elements.push_back({kGmshPoint, 0, {node}, {}, 0});
      model.elements[where->second].physical.push_back(physical_tag(g));
    }
  }
}

void grow_box(std::array<double, 6>& box, const Mesh& mesh, int node) {
  for (int c = 0; c < 3; ++c) {
    box[c] = std::min(box[c], mesh.rest_positions[3 * node + c]);
    box[3 + c] = std::max(box[3 + c], mesh.rest_positions[3 * node + c]);
  }
}

/// One entity per (dimension, physical tag set); one per point element.
void assign_entities(const Mesh& mesh, MshModel& model) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::map<std::pair<int, std::vector<int>>, std::size_t> by_signature;
  std::array<int, 4> next_tag{1, 1, 1, 1};
  for (MshElement& element : model.elements) {
    std::size_t index = model.entities.size();
    if (element.dim == 0) {
      model.entities.push_back({0, next_tag[0]++, element.physical, {inf, inf, inf, -inf, -inf, -inf}});
    } else {
      const auto [where, inserted] = by_signature.emplace(std::make_pair(element.dim, element.physical), index);
      if (inserted)
        model.entities.push_back(
            {element.dim, next_tag[element.dim]++, element.physical, {inf, inf, inf, -inf, -inf, -inf}});
      index = where->second;
    }
    Entity& entity = model.entities[index];
    element.entity = entity.tag;
    for (int node : element.nodes) grow_box(entity.box, mesh, node);
  }
}

void collect_names(const Mesh& mesh, MshModel& model) {
  std::set<std::array<int, 2>> names;
  std::vector<char> used(mesh.groups.size(), 0);
  for (const MshElement& element : model.elements)
    for (int tag : element.physical) {
      names.insert({element.dim, tag - 1});
      used[tag - 1] = 1;
    }
  for (std::size_t g = 0; g < mesh.groups.size(); ++g)
    if (!used[g]) names.insert({mesh.groups[g].dim, static_cast<int>(g)});
  model.names.assign(names.begin(), names.end());
}

MshModel build_model(const Mesh& mesh) {
  MshModel model;
  add_cells(mesh, model);
  add_facets(mesh, model);
  add_points(mesh, model);
  assign_entities(mesh, model);
  collect_names(mesh, model);
  return model;
}

// --- Printing ----------------------------------------------------------------

/// Appends numbers and words to a string, exactly and fast.
class Text {
 public:
  Text& operator<<(std::string_view word) {
    out_.append(word);
    return *this;
  }
  Text& operator<<(char c) {
    out_.push_back(c);
    return *this;
  }
  Text& operator<<(long value) { return number(value); }
  Text& operator<<(int value) { return number(value); }
  Text& operator<<(std::size_t value) { return number(value); }
  /// Shortest text that reads back as exactly `value`.
  Text& operator<<(double value) { return number(value); }
  const std::string& str() const { return out_; }

 private:
  template <class T>
  Text& number(T value) {
    char buffer[32];
    out_.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
    return *this;
  }
  std::string out_;
};

void print_names(Text& text, const Mesh& mesh, const MshModel& model) {
  if (model.names.empty()) return;
  text << "$PhysicalNames\n" << model.names.size() << '\n';
  for (const auto& [dim, group] : model.names)
    text << dim << ' ' << physical_tag(group) << " \"" << mesh.groups[group].name << "\"\n";
  text << "$EndPhysicalNames\n";
}

void print_entities(Text& text, const MshModel& model) {
  std::array<int, 4> counts{};
  for (const Entity& entity : model.entities) ++counts[entity.dim];
  text << "$Entities\n" << counts[0] << ' ' << counts[1] << ' ' << counts[2] << ' ' << counts[3] << '\n';
  for (int dim = 0; dim <= 3; ++dim)
    for (const Entity& entity : model.entities) {
      if (entity.dim != dim) continue;
      text << entity.tag;
      for (int c = 0; c < (dim == 0 ? 3 : 6); ++c) text << ' ' << entity.box[c];
      text << ' ' << entity.physical.size();
      for (int tag : entity.physical) text << ' ' << tag;
      text << (dim == 0 ? "\n" : " 0\n");  // no bounding entities
    }
  text << "$EndEntities\n";
}

void print_coordinates(Text& text, const Mesh& mesh, int node) {
  text << mesh.rest_positions[3 * node] << ' ' << mesh.rest_positions[3 * node + 1] << ' '
       << mesh.rest_positions[3 * node + 2] << '\n';
}

/// All nodes in one block, in tag order, classified on the first cell entity
/// (readers number nodes in file order; Gmsh looks element nodes up by tag).
void print_nodes41(Text& text, const Mesh& mesh, const MshModel& model) {
  const MshElement& first_cell = model.elements.front();
  const int n = mesh.node_count();
  text << "$Nodes\n1 " << n << " 1 " << n << '\n';
  text << first_cell.dim << ' ' << first_cell.entity << " 0 " << n << '\n';
  for (int node = 0; node < n; ++node) text << node + 1 << '\n';
  for (int node = 0; node < n; ++node) print_coordinates(text, mesh, node);
  text << "$EndNodes\n";
}

void print_elements41(Text& text, const MshModel& model) {
  std::map<std::array<int, 3>, std::vector<std::size_t>> blocks;  // (dim, entity, type) -> elements
  for (std::size_t e = 0; e < model.elements.size(); ++e) {
    const MshElement& element = model.elements[e];
    blocks[{element.dim, element.entity, element.type}].push_back(e);
  }
  text << "$Elements\n" << blocks.size() << ' ' << model.elements.size() << " 1 " << model.elements.size() << '\n';
  for (const auto& [key, members] : blocks) {
    text << key[0] << ' ' << key[1] << ' ' << key[2] << ' ' << members.size() << '\n';
    for (std::size_t e : members) {
      text << e + 1;
      for (int node : model.elements[e].nodes) text << ' ' << node + 1;
      text << '\n';
    }
  }
  text << "$EndElements\n";
}

void print_msh41(Text& text, const Mesh& mesh, const MshModel& model) {
  text << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  print_names(text, mesh, model);
  print_entities(text, model);
  print_nodes41(text, mesh, model);
  print_elements41(text, model);
}

/// Format 2.2: one line per (element, physical tag); physical 0 when it has none.
void print_msh22(Text& text, const Mesh& mesh, const MshModel& model) {
  text << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  print_names(text, mesh, model);
  text << "$Nodes\n" << mesh.node_count() << '\n';
  for (int node = 0; node < mesh.node_count(); ++node) {
    text << node + 1 << ' ';
    print_coordinates(text, mesh, node);
  }
  text << "$EndNodes\n";
  std::size_t lines = 0;
  for (const MshElement& element : model.elements) lines += std::max<std::size_t>(1, element.physical.size());
  text << "$Elements\n" << lines << '\n';
  long tag = 1;
  for (const MshElement& element : model.elements) {
    const std::vector<int> physical = element.physical.empty() ? std::vector<int>{0} : element.physical;
    for (int group : physical) {
      text << tag++ << ' ' << element.type << " 2 " << group << ' ' << element.entity;
      for (int node : element.nodes) text << ' ' << node + 1;
      text << '\n';
    }
  }
  text << "$EndElements\n";
}

}  // namespace

MshFormat parse_msh_format(std::string_view text) {
  if (text == "4.1") return MshFormat::v41;
  if (text == "2.2") return MshFormat::v22;
  throw InputError("unknown .msh format '" + std::string(text) + "' (expected 4.1 or 2.2)");
}

void write_msh(const std::string& path, const Mesh& mesh, MshFormat format) {
  if (mesh.cell_count() == 0) throw std::invalid_argument(path + ": the mesh has no cells to write");
  const MshModel model = build_model(mesh);
  Text text;
  if (format == MshFormat::v41) print_msh41(text, mesh, model);
  else print_msh22(text, mesh, model);
  write_atomically(path, [&](std::ostream& out) { out << text.str(); });
}

}  // namespace tensormass::io
