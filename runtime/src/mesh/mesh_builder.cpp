#include "mesh/mesh_builder.hpp"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <map>
#include <memory>
#include <unordered_map>

#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass::detail {

// ---------------------------------------------------------------- shapes

namespace {

const std::vector<Shape>& shapes() {
  static const std::vector<Shape> table = [] {
    std::vector<Shape> result{{"point", 0, 1, 1, nullptr}, {"line2", 1, 2, 1, nullptr}, {"line3", 1, 3, 2, nullptr}};
    for (const tm_element_info* e : Registry::instance().elements())
      result.push_back({e->name, e->dim, e->nodes, e->order, e});
    return result;
  }();
  return table;
}

}  // namespace

const Shape* find_shape(std::string_view name) {
  for (const Shape& shape : shapes())
    if (shape.name == name) return &shape;
  return nullptr;
}

const Shape* shape_of(const tm_element_info* element) {
  for (const Shape& shape : shapes())
    if (shape.element == element) return &shape;
  return nullptr;
}

// ---------------------------------------------------------------- builder

/// File node id -> raw node index: a dense table when ids are compact, a hash map otherwise.
/// Ids may be any 64-bit values: differences are taken as unsigned, where
/// they cannot overflow.
class MeshBuilder::NodeIndex {
 public:
  /// Indexes `ids`; throws at the second occurrence of a duplicate id.
  NodeIndex(const std::string& source, const std::vector<long>& ids, const std::vector<Location>& where) {
    if (ids.empty()) throw InputError(source + ": the file has no nodes");
    const auto [lo, hi] = std::minmax_element(ids.begin(), ids.end());
    min_id_ = *lo;
    const unsigned long long span_minus_one = offset_of(*hi);
    dense_mode_ = span_minus_one < 4 * static_cast<unsigned long long>(ids.size()) + 1024;
    if (dense_mode_) dense_.assign(static_cast<std::size_t>(span_minus_one) + 1, -1);
    else sparse_.reserve(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) {
      int& slot = dense_mode_ ? dense_[static_cast<std::size_t>(offset_of(ids[i]))]
                              : sparse_.try_emplace(ids[i], -1).first->second;
      if (slot >= 0)
        throw InputError(format_location(source, where[i]) + ": duplicate node id " + std::to_string(ids[i]) +
                         " (first defined at " + format_location(source, where[static_cast<std::size_t>(slot)]) + ")");
      slot = static_cast<int>(i);
    }
  }

  /// The raw index of node `id`, or -1.
  int find(long id) const {
    if (!dense_mode_) {
      const auto found = sparse_.find(id);
      return found == sparse_.end() ? -1 : found->second;
    }
    if (id < min_id_) return -1;
    const unsigned long long k = offset_of(id);
    return k < dense_.size() ? dense_[static_cast<std::size_t>(k)] : -1;
  }

 private:
  /// `id - min_id_` for id >= min_id_, exact for any two 64-bit ids.
  unsigned long long offset_of(long id) const {
    return static_cast<unsigned long long>(id) - static_cast<unsigned long long>(min_id_);
  }

  long min_id_ = 0;
  bool dense_mode_ = true;
  std::vector<int> dense_;
  std::unordered_map<long, int> sparse_;
};

/// The raw elements resolved against the nodes, shared by the build steps.
struct MeshBuilder::Resolved {
  int dim = 0;
  std::vector<int> raw;       ///< per element node entry: raw node index
  std::vector<int> renumber;  ///< raw node index -> mesh node, -1 when used by no cell
  std::vector<int> first;     ///< per element: the first element with the same shape and nodes
  std::vector<int> cell_of;   ///< per element: mesh-wide cell index, -1 when not a cell
};

namespace {

/// Index of the first element with the same shape and nodes, for each
/// element. Elements are sorted by a hash of their shape and nodes (16
/// bytes each, against some 48 in a hash map at a million elements), and
/// only those of one hash are compared.
std::vector<int> find_duplicates(const std::vector<const Shape*>& shapes, const std::vector<std::size_t>& offsets,
                                 const std::vector<int>& nodes) {
  const auto same = [&](std::size_t a, std::size_t b) {
    return shapes[a] == shapes[b] && std::equal(nodes.begin() + static_cast<std::ptrdiff_t>(offsets[a]),
                                                nodes.begin() + static_cast<std::ptrdiff_t>(offsets[a + 1]),
                                                nodes.begin() + static_cast<std::ptrdiff_t>(offsets[b]),
                                                nodes.begin() + static_cast<std::ptrdiff_t>(offsets[b + 1]));
  };
  std::vector<std::pair<std::size_t, int>> hashed(shapes.size());
  for (std::size_t e = 0; e < shapes.size(); ++e) {
    std::size_t h = std::hash<const void*>()(shapes[e]);
    for (std::size_t k = offsets[e]; k < offsets[e + 1]; ++k) h = h * 1000003u ^ static_cast<std::size_t>(nodes[k]);
    hashed[e] = {h, static_cast<int>(e)};
  }
  std::sort(hashed.begin(), hashed.end());  // by hash, then by element: the first of equals comes first
  std::vector<int> first(shapes.size());
  for (std::size_t run = 0; run < hashed.size();) {
    std::size_t end = run + 1;
    while (end < hashed.size() && hashed[end].first == hashed[run].first) ++end;
    for (std::size_t i = run; i < end; ++i) {
      const auto e = static_cast<std::size_t>(hashed[i].second);
      first[e] = hashed[i].second;
      for (std::size_t j = run; j < i; ++j)  // the earlier elements of this hash, in order
        if (const auto other = static_cast<std::size_t>(hashed[j].second);
            first[other] == hashed[j].second && same(e, other)) {
          first[e] = hashed[j].second;
          break;
        }
    }
    run = end;
  }
  return first;
}

void sort_unique(std::vector<int>& values) {
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
}

}  // namespace

MeshBuilder::MeshBuilder(std::string source, std::string element_word)
    : source_(std::move(source)), element_word_(std::move(element_word)) {}

void MeshBuilder::reserve_nodes(std::size_t count) {
  node_ids_.reserve(count);
  xyz_.reserve(3 * count);
  node_where_.reserve(count);
}

void MeshBuilder::add_node(long id, const double xyz[3], Location where) {
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(xyz[c]))
      throw InputError(format_location(source_, where) + ": node " + std::to_string(id) +
                       " has a non-finite coordinate (" + "xyz"[c] + " = " + std::to_string(xyz[c]) + ")");
  node_ids_.push_back(id);
  xyz_.insert(xyz_.end(), xyz, xyz + 3);
  node_where_.push_back(where);
}

void MeshBuilder::reserve_elements(std::size_t count) {
  const std::size_t total = shapes_.size() + count;
  shapes_.reserve(total);
  element_ids_.reserve(total);
  node_offsets_.reserve(total + 1);
  group_offsets_.reserve(total + 1);
  element_where_.reserve(total);
}

void MeshBuilder::add_element(const Shape& shape, long id, std::span<const long> nodes, std::span<const long> groups,
                              Location where) {
  shapes_.push_back(&shape);
  element_ids_.push_back(id);
  element_nodes_.insert(element_nodes_.end(), nodes.begin(), nodes.end());
  node_offsets_.push_back(element_nodes_.size());
  element_groups_.insert(element_groups_.end(), groups.begin(), groups.end());
  group_offsets_.push_back(element_groups_.size());
  element_where_.push_back(where);
}

void MeshBuilder::fail_element(std::size_t e, const std::string& message) const {
  throw InputError(format_location(source_, element_where_[e]) + ": " + element_word_ + " " +
                   std::to_string(element_ids_[e]) + " (" + shapes_[e]->name + ") " + message);
}

int MeshBuilder::mesh_dimension() const {
  if (shapes_.empty()) throw InputError(source_ + ": the file has no elements");
  int dim = 0;
  for (const Shape* shape : shapes_) dim = std::max(dim, shape->dim);
  if (dim < 2)
    throw InputError(source_ + ": no 2D or 3D elements (the highest element dimension is " + std::to_string(dim) + ")");
  return dim;
}

MeshBuilder::Resolved MeshBuilder::resolve() const {
  Resolved r;
  r.dim = mesh_dimension();
  const NodeIndex index(source_, node_ids_, node_where_);
  r.raw.resize(element_nodes_.size());
  for (std::size_t e = 0; e < shapes_.size(); ++e)
    for (std::size_t k = node_offsets_[e]; k < node_offsets_[e + 1]; ++k) {
      r.raw[k] = index.find(element_nodes_[k]);
      if (r.raw[k] < 0)
        fail_element(e, "refers to node " + std::to_string(element_nodes_[k]) + ", which the file does not define");
    }
  r.renumber.assign(node_ids_.size(), -1);
  for (std::size_t e = 0; e < shapes_.size(); ++e)
    if (shapes_[e]->dim == r.dim)
      for (std::size_t k = node_offsets_[e]; k < node_offsets_[e + 1]; ++k)
        r.renumber[static_cast<std::size_t>(r.raw[k])] = 0;
  int next = 0;
  for (int& number : r.renumber)
    if (number == 0) number = next++;
  r.first = find_duplicates(shapes_, node_offsets_, r.raw);
  r.cell_of.assign(shapes_.size(), -1);
  return r;
}

void MeshBuilder::fill_nodes(Mesh& mesh, const Resolved& r) const {
  const auto count =
      static_cast<std::size_t>(std::count_if(r.renumber.begin(), r.renumber.end(), [](int n) { return n >= 0; }));
  mesh.rest_positions.resize(3 * count);
  mesh.node_source_ids.resize(count);
  for (std::size_t i = 0; i < r.renumber.size(); ++i) {
    if (r.renumber[i] < 0) continue;
    const auto n = static_cast<std::size_t>(r.renumber[i]);
    mesh.node_source_ids[n] = node_ids_[i];
    for (std::size_t c = 0; c < 3; ++c) mesh.rest_positions[3 * n + c] = xyz_[3 * i + c];
  }
}

void MeshBuilder::fill_blocks(Mesh& mesh, Resolved& r) const {
  int next_cell = 0;
  for (const tm_element_info* element : Registry::instance().elements()) {
    if (element->dim != r.dim) continue;
    ElementBlock block;
    block.element = element;
    block.first_cell = next_cell;
    for (std::size_t e = 0; e < shapes_.size(); ++e) {
      if (shapes_[e]->element != element || r.first[e] != static_cast<int>(e)) continue;
      for (std::size_t k = node_offsets_[e]; k < node_offsets_[e + 1]; ++k)
        block.connectivity.push_back(r.renumber[static_cast<std::size_t>(r.raw[k])]);
      block.source_ids.push_back(element_ids_[e]);
      r.cell_of[e] = next_cell++;
    }
    if (block.count() > 0) mesh.blocks.push_back(std::move(block));
  }
}

void MeshBuilder::add_to_group(Group& group, std::size_t e, const Resolved& r) const {
  const Shape& shape = *shapes_[e];
  group.dim = std::max(group.dim, shape.dim);
  const bool facet = shape.dim == r.dim - 1;
  for (std::size_t k = node_offsets_[e]; k < node_offsets_[e + 1]; ++k) {
    const int node = r.renumber[static_cast<std::size_t>(r.raw[k])];
    if (node < 0)
      fail_element(e, "of group '" + group.name + "' uses node " + std::to_string(element_nodes_[k]) +
                          ", which belongs to no " + std::to_string(r.dim) + "D element");
    group.nodes.push_back(node);
    if (facet) group.facets.nodes.push_back(node);
  }
  if (shape.dim == r.dim) group.cells.push_back(r.cell_of[e]);
  if (facet) {
    group.facets.offsets.push_back(static_cast<int>(group.facets.nodes.size()));
    group.facets.orders.push_back(shape.order);
  }
}

void MeshBuilder::fill_groups(Mesh& mesh, const Resolved& r, const std::function<GroupInfo(long key)>& describe) const {
  // (key, first element) pairs: key order, then file order; duplicates once.
  std::vector<std::pair<long, int>> members;
  for (std::size_t e = 0; e < shapes_.size(); ++e)
    for (std::size_t k = group_offsets_[e]; k < group_offsets_[e + 1]; ++k)
      members.emplace_back(element_groups_[k], r.first[e]);
  std::sort(members.begin(), members.end());
  members.erase(std::unique(members.begin(), members.end()), members.end());
  std::map<std::string, std::size_t> by_name;
  std::size_t target = 0;
  for (std::size_t m = 0; m < members.size(); ++m) {
    if (m == 0 || members[m].first != members[m - 1].first) {
      const GroupInfo info = describe(members[m].first);
      const auto [it, added] = by_name.try_emplace(info.name, mesh.groups.size());
      if (added) mesh.groups.push_back(Group{info.name, -1, {}, {}, {}});
      target = it->second;
      mesh.groups[target].dim = std::max(mesh.groups[target].dim, info.dim);
    }
    add_to_group(mesh.groups[target], static_cast<std::size_t>(members[m].second), r);
  }
  for (Group& group : mesh.groups) {
    sort_unique(group.nodes);
    sort_unique(group.cells);
  }
}

Mesh MeshBuilder::build(const std::function<GroupInfo(long key)>& describe) {
  Resolved r = resolve();
  Mesh mesh;
  mesh.dim = r.dim;
  mesh.source = source_;
  fill_nodes(mesh, r);
  fill_blocks(mesh, r);
  fill_groups(mesh, r, describe);
  if (r.dim == 2) flatten_2d(mesh);
  mesh.validate();
  return mesh;
}

void MeshBuilder::flatten_2d(Mesh& mesh) const {
  double extent = 0;
  for (double x : mesh.rest_positions) extent = std::max(extent, std::abs(x));
  const double tolerance = 1e-9 * std::max(1.0, extent);
  for (int n = 0; n < mesh.node_count(); ++n) {
    double& z = mesh.rest_positions[3 * static_cast<std::size_t>(n) + 2];
    if (std::abs(z) > tolerance)
      throw InputError(source_ + ": the highest elements are 2D, but node " +
                       std::to_string(mesh.node_source_ids[static_cast<std::size_t>(n)]) +
                       " has z = " + std::to_string(z) +
                       "; 2D meshes must lie in the plane z = 0 (for a 3D mesh, the file must hold its volume "
                       "elements: with Gmsh, add a Physical Volume or set Mesh.SaveAll = 1)");
    z = 0;
  }
}

}  // namespace tensormass::detail
