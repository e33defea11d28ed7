// Refinement, balance and coarsening of the hierarchy (see
// hierarchical_mesh.hpp); the leaf mesh is built in hierarchical_leaf_mesh.cpp.
#include "tensormass/refinement/hierarchical_mesh.hpp"

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "refinement/node_pairs.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/mesh/mesh_conformity.hpp"
#include "tensormass/refinement/split_patterns.hpp"
#include "tensormass/refinement/transition_patterns.hpp"

namespace tensormass {
namespace {

using detail::edge_key;
using detail::squared_distance;

/// A quad face's key: its lowest corner and the corner opposite it.
std::uint64_t face_key(std::span<const int> face) {
  const auto lowest = static_cast<std::size_t>(std::min_element(face.begin(), face.end()) - face.begin());
  return edge_key(face[lowest], face[(lowest + 2) % 4]);
}

const double* at(std::span<const double> positions, int node) { return &positions[3 * static_cast<std::size_t>(node)]; }

/// Twice the signed area of the polygon `corners` in the x-y plane.
double twice_signed_area(std::span<const double> positions, std::span<const int> corners) {
  double sum = 0;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const double* p = at(positions, corners[k]);
    const double* q = at(positions, corners[(k + 1) % corners.size()]);
    sum += p[0] * q[1] - q[0] * p[1];
  }
  return sum;
}

/// Six times the signed volume of a 3D cell: the sum, over its faces
/// (outward), of the fan triangles around each face's mean point.
double six_signed_volume(std::span<const double> positions, const tm_element_info& element,
                         std::span<const int> nodes) {
  double sum = 0;
  for (int f = 0; f < element.face_count; ++f) {
    const int size = element.face_sizes[f];
    const int* face = element.faces + element.face_offsets[f];
    double mean[3] = {0, 0, 0};
    for (int k = 0; k < size; ++k)
      for (int c = 0; c < 3; ++c) mean[c] += at(positions, nodes[face[k]])[c] / size;
    for (int k = 0; k < size; ++k) {
      const double* p = at(positions, nodes[face[k]]);
      const double* q = at(positions, nodes[face[(k + 1) % size]]);
      sum += mean[0] * (p[1] * q[2] - p[2] * q[1]) - mean[1] * (p[0] * q[2] - p[2] * q[0]) +
             mean[2] * (p[0] * q[1] - p[1] * q[0]);
    }
  }
  return sum;
}

std::string mesh_name(const Mesh& mesh) { return mesh.source.empty() ? std::string("mesh") : mesh.source; }

void check_cells(const Mesh& mesh) {
  for (const ElementBlock& block : mesh.blocks) {
    const std::string name = block.element->name;
    if (!has_split_pattern(name))
      throw InputError(mesh_name(mesh) + ": " + name +
                       " cells cannot be refined (refinement supports quad4 and tri3 in 2D, hex8, tet4, prism6 and "
                       "pyramid5 in 3D)");
    for (int local = 0; local < block.count(); ++local) {
      const auto nodes = block.cell_nodes(local);
      const double measure = mesh.dim == 2 ? twice_signed_area(mesh.rest_positions, nodes)
                                           : six_signed_volume(mesh.rest_positions, *block.element, nodes);
      if (!(measure > 0))
        throw InputError(mesh_name(mesh) + ": " + mesh.describe_cell(block.first_cell + local) +
                         (mesh.dim == 2
                              ? " is clockwise or flat; refinement needs counter-clockwise cells of positive area"
                              : " is inverted or flat; refinement needs cells of positive volume"));
    }
  }
}

/// Every face (edge in 2D) of every cell, by its sorted corner nodes.
std::set<std::vector<int>> cell_faces(const Mesh& mesh) {
  std::set<std::vector<int>> faces;
  for (const ElementBlock& block : mesh.blocks) {
    const tm_element_info& element = *block.element;
    for (int local = 0; local < block.count(); ++local) {
      const auto nodes = block.cell_nodes(local);
      const int count = mesh.dim == 2 ? element.edge_count : element.face_count;
      for (int f = 0; f < count; ++f) {
        std::vector<int> face;
        if (mesh.dim == 2) {
          for (int k = 0; k < 2; ++k) face.push_back(nodes[element.edges[f * element.edge_size + k]]);
        } else {
          for (int k = 0; k < element.face_sizes[f]; ++k)
            face.push_back(nodes[element.faces[element.face_offsets[f] + k]]);
        }
        std::sort(face.begin(), face.end());
        faces.insert(std::move(face));
      }
    }
  }
  return faces;
}

/// Group facets are first-order faces of cells: refinement cuts them as it cuts those faces.
void check_groups(const Mesh& mesh) {
  const std::set<std::vector<int>> faces = cell_faces(mesh);
  for (const Group& group : mesh.groups)
    for (int f = 0; f < group.facets.count(); ++f) {
      const int size = group.facets.offsets[f + 1] - group.facets.offsets[f];
      const bool supported = mesh.dim == 2 ? size == 2 : (size == 3 || size == 4);
      if (!supported)
        throw InputError(mesh_name(mesh) + ": group '" + group.name + "' has a facet of " + std::to_string(size) +
                         " nodes; refinement supports " +
                         (mesh.dim == 2 ? "line2 facets" : "tri3 and quad4 facets (first-order faces)"));
      std::vector<int> facet(group.facets.nodes.begin() + group.facets.offsets[f],
                             group.facets.nodes.begin() + group.facets.offsets[f + 1]);
      std::sort(facet.begin(), facet.end());
      if (!faces.count(facet))
        throw InputError(mesh_name(mesh) + ": facet " + std::to_string(f) + " of group '" + group.name + "' is not a " +
                         (mesh.dim == 2 ? "edge" : "face") +
                         " of any cell; refinement cuts facets as it cuts the faces of the cells");
    }
}

/// Throws InputError unless `mesh` is a mesh the hierarchy can wrap.
void check_refinable(const Mesh& mesh) {
  mesh.validate();
  check_cells(mesh);
  check_groups(mesh);
  const ConformityReport conformity = check_conformity(mesh);
  if (conformity.overused_faces > 0)
    throw InputError(mesh_name(mesh) + ": " + std::to_string(conformity.overused_faces) + " " +
                     (mesh.dim == 2 ? "edges" : "faces") +
                     " are shared by more than two cells; refinement needs a conforming mesh");
}

}  // namespace

// --- Construction ------------------------------------------------------------------

HierarchicalMesh::HierarchicalMesh(Mesh original) : original_(std::move(original)) {
  check_refinable(original_);
  for (const char* name : transition_element_names(original_.dim))
    transition_elements_.push_back(Registry::instance().element(name));
  original_nodes_ = original_.node_count();
  positions_ = original_.rest_positions;
  node_parents_.assign(static_cast<std::size_t>(original_nodes_), NodeParents{});
  corner_uses_.assign(static_cast<std::size_t>(original_nodes_), 0);
  add_original_cells();
  old_node_count_ = original_nodes_;
  rebuild();
}

void HierarchicalMesh::add_original_cells() {
  for (const ElementBlock& block : original_.blocks)
    for (int local = 0; local < block.count(); ++local) {
      HierarchyCell cell;
      cell.element = block.element;
      const auto nodes = block.cell_nodes(local);
      std::copy(nodes.begin(), nodes.end(), cell.corners.begin());
      cell.origin = block.first_cell + local;
      add_cell(cell);
    }
}

// --- Nodes and cells ----------------------------------------------------------------

int HierarchicalMesh::add_node(const NodeParents& parents) {
  double position[3] = {0, 0, 0};
  for (int k = 0; k < parents.count; ++k)
    for (int c = 0; c < 3; ++c) position[c] += positions_[3 * static_cast<std::size_t>(parents.nodes[k]) + c];
  for (double& x : position) x /= parents.count;
  positions_.insert(positions_.end(), position, position + 3);
  node_parents_.push_back(parents);
  corner_uses_.push_back(0);
  return static_cast<int>(node_parents_.size()) - 1;
}

int HierarchicalMesh::find_midpoint(int a, int b) const {
  const auto found = midpoints_.find(edge_key(a, b));
  return found == midpoints_.end() ? -1 : found->second;
}

int HierarchicalMesh::midpoint(int a, int b) {
  if (const int node = find_midpoint(a, b); node >= 0) return node;
  const int node = add_node({{a, b, -1, -1, -1, -1, -1, -1}, 2});
  midpoints_.emplace(edge_key(a, b), node);
  return node;
}

int HierarchicalMesh::find_face_centre(std::span<const int> face) const {
  const auto found = face_centres_.find(face_key(face));
  return found == face_centres_.end() ? -1 : found->second;
}

int HierarchicalMesh::face_centre(std::span<const int> face) {
  if (const int node = find_face_centre(face); node >= 0) return node;
  NodeParents parents;
  for (int corner : face) parents.nodes[parents.count++] = corner;
  const int node = add_node(parents);
  face_centres_.emplace(face_key(face), node);
  return node;
}

int HierarchicalMesh::centre_node(int cell) {
  if (cells_[cell].centre < 0) {
    NodeParents parents;
    parents.nodes = cells_[cell].corners;
    parents.count = cells_[cell].corner_count();
    cells_[cell].centre = add_node(parents);
  }
  return cells_[cell].centre;
}

void HierarchicalMesh::add_cell(const HierarchyCell& cell) {
  cells_.push_back(cell);
  cell_sources_.push_back(-1);
  for (int k = 0; k < cell.corner_count(); ++k) ++corner_uses_[cell.corners[k]];
}

std::array<int, 4> HierarchicalMesh::hanging_midpoints(const HierarchyCell& leaf) const {
  std::array<int, 4> midpoints{-1, -1, -1, -1};
  const int n = leaf.corner_count();
  for (int k = 0; k < n; ++k) midpoints[k] = find_midpoint(leaf.corners[k], leaf.corners[(k + 1) % n]);
  return midpoints;
}

bool HierarchicalMesh::has_hanging_nodes(const HierarchyCell& leaf) const {
  const tm_element_info& element = *leaf.element;
  for (int e = 0; e < element.edge_count; ++e) {
    const int* edge = element.edges + e * element.edge_size;
    if (find_midpoint(leaf.corners[edge[0]], leaf.corners[edge[1]]) >= 0) return true;
  }
  return false;
}

std::vector<int> HierarchicalMesh::face_corners(const HierarchyCell& cell, int f) const {
  const tm_element_info& element = *cell.element;
  const int* face = element.faces + element.face_offsets[f];
  std::vector<int> corners;
  for (int k = 0; k < element.face_sizes[f]; ++k) corners.push_back(cell.corners[face[k]]);
  return corners;
}

// --- Refinement ---------------------------------------------------------------------

/// tet4: the octahedron's shortest diagonal (ties: the first), so children stay well shaped.
int HierarchicalMesh::tet_diagonal(const HierarchyCell& cell) {
  const std::array<int, 8>& c = cell.corners;
  const std::array<double, 3> lengths{squared_distance(positions_, midpoint(c[0], c[1]), midpoint(c[2], c[3])),
                                      squared_distance(positions_, midpoint(c[0], c[2]), midpoint(c[1], c[3])),
                                      squared_distance(positions_, midpoint(c[0], c[3]), midpoint(c[1], c[2]))};
  return static_cast<int>(std::min_element(lengths.begin(), lengths.end()) - lengths.begin());
}

void HierarchicalMesh::split(int cell) {
  const std::string_view name = cells_[cell].element->name;
  const SplitPattern& pattern = split_pattern(name, name == "tet4" ? tet_diagonal(cells_[cell]) : 0);
  const std::array<int, 8> c = cells_[cell].corners;
  std::vector<int> nodes;
  for (const SplitNode& node : pattern.nodes) {
    if (node.count == 1) nodes.push_back(c[node.corners[0]]);
    else if (node.count == 2) nodes.push_back(midpoint(c[node.corners[0]], c[node.corners[1]]));
    else if (node.count == 4 && original_.dim == 3) {
      const std::array<int, 4> face{c[node.corners[0]], c[node.corners[1]], c[node.corners[2]], c[node.corners[3]]};
      nodes.push_back(face_centre(face));
    } else nodes.push_back(centre_node(cell));  // quad4's (2D) or hex8's centre
  }
  for (std::size_t k = 0; k < pattern.children.size(); ++k) {
    HierarchyCell child;
    child.element = pattern.child_elements.empty()
                        ? cells_[cell].element
                        : Registry::instance().element(std::string(pattern.child_elements[k]));
    for (std::size_t n = 0; n < pattern.children[k].size(); ++n)
      child.corners[n] = nodes[static_cast<std::size_t>(pattern.children[k][n])];
    child.parent = cell;
    child.level = cells_[cell].level + 1;
    child.origin = cells_[cell].origin;
    add_cell(child);
    cells_[cell].children[k] = hierarchy_size() - 1;
    cell_sources_.back() = cell_sources_[cell];
  }
}

/// Whether a neighbour has split an edge of `cell` twice (or, in 3D, the
/// inner triangle of a red-cut triangular face): 2:1 balance broken.
bool HierarchicalMesh::split_twice(const HierarchyCell& cell) const {
  const tm_element_info& element = *cell.element;
  for (int e = 0; e < element.edge_count; ++e) {
    const int* edge = element.edges + e * element.edge_size;
    const int a = cell.corners[edge[0]], b = cell.corners[edge[1]];
    const int m = find_midpoint(a, b);
    if (m >= 0 && (find_midpoint(a, m) >= 0 || find_midpoint(m, b) >= 0)) return true;
  }
  if (original_.dim == 2) return false;
  for (int f = 0; f < element.face_count; ++f) {
    if (element.face_sizes[f] != 3) continue;
    const std::vector<int> face = face_corners(cell, f);
    const int m0 = find_midpoint(face[0], face[1]), m1 = find_midpoint(face[1], face[2]),
              m2 = find_midpoint(face[2], face[0]);
    if (m0 < 0 || m1 < 0 || m2 < 0) continue;
    if (find_midpoint(m0, m1) >= 0 || find_midpoint(m1, m2) >= 0 || find_midpoint(m2, m0) >= 0) return true;
  }
  return false;
}

void HierarchicalMesh::balance() {
  for (bool changed = true; changed;) {
    changed = false;
    for (int cell = 0; cell < hierarchy_size(); ++cell)
      if (cells_[cell].element && cells_[cell].is_leaf() && split_twice(cells_[cell])) {
        split(cell);
        changed = true;
      }
  }
}

std::vector<int> HierarchicalMesh::marked_owners(std::span<const int> marked_cells, const char* operation) const {
  const int count = leaf_.cell_count();
  std::vector<int> owners;
  for (int cell : marked_cells) {
    if (cell < 0 || cell >= count)
      throw InputError(std::string(operation) + ": cell " + std::to_string(cell) +
                       " is not a cell of the leaf mesh (0.." + std::to_string(count - 1) + ")");
    owners.push_back(leaf_owners_[cell]);
  }
  std::sort(owners.begin(), owners.end());
  owners.erase(std::unique(owners.begin(), owners.end()), owners.end());
  return owners;
}

LeafTransfer HierarchicalMesh::refine(std::span<const int> marked_cells, int max_level) {
  if (max_level < 0) throw InputError("refine: max_level must be at least 0, got " + std::to_string(max_level));
  const std::vector<int> owners = marked_owners(marked_cells, "refine");
  old_node_count_ = static_cast<int>(node_parents_.size());
  cell_sources_ = first_leaf_cell_;
  for (int cell : owners)
    if (cells_[cell].level < max_level) split(cell);
  balance();
  return rebuild();
}

// --- Coarsening ---------------------------------------------------------------------

void HierarchicalMesh::merge(int parent) {
  HierarchyCell& cell = cells_[parent];
  cell_sources_[parent] = cell_sources_[cell.children[0]];
  for (int child : cell.children) {
    if (child < 0) continue;
    HierarchyCell& removed = cells_[child];
    for (int k = 0; k < removed.corner_count(); ++k) --corner_uses_[removed.corners[k]];
    removed.element = nullptr;
  }
  cell.children.fill(-1);
  // Midpoints the neighbours have not split go (a tet's inner edges have none).
  const tm_element_info& element = *cell.element;
  for (int e = 0; e < element.edge_count; ++e) {
    const int* edge = element.edges + e * element.edge_size;
    const std::uint64_t key = edge_key(cell.corners[edge[0]], cell.corners[edge[1]]);
    if (const auto found = midpoints_.find(key); found != midpoints_.end() && corner_uses_[found->second] == 0)
      midpoints_.erase(found);
  }
}

LeafTransfer HierarchicalMesh::coarsen(std::span<const int> marked_cells) {
  const std::vector<int> owners = marked_owners(marked_cells, "coarsen");
  old_node_count_ = static_cast<int>(node_parents_.size());
  cell_sources_ = first_leaf_cell_;
  std::vector<int> parents;
  for (int cell : owners)
    if (cells_[cell].parent >= 0) parents.push_back(cells_[cell].parent);
  std::sort(parents.begin(), parents.end());
  parents.erase(std::unique(parents.begin(), parents.end()), parents.end());
  const auto all_marked_leaves = [&](int parent) {
    const HierarchyCell& cell = cells_[parent];
    return std::all_of(cell.children.begin(), cell.children.begin() + cell.child_count(), [&](int child) {
      return cells_[child].is_leaf() && std::binary_search(owners.begin(), owners.end(), child);
    });
  };
  parents.erase(std::remove_if(parents.begin(), parents.end(), [&](int p) { return !all_marked_leaves(p); }),
                parents.end());
  // Deepest first, so that a neighbour merged in the same call no longer blocks.
  std::stable_sort(parents.begin(), parents.end(), [&](int p, int q) { return cells_[p].level > cells_[q].level; });
  for (int parent : parents)
    if (!split_twice(cells_[parent])) merge(parent);
  return rebuild();
}

std::vector<int> HierarchicalMesh::leaves_per_level() const {
  std::vector<int> counts;
  for (const HierarchyCell& cell : cells_) {
    if (!cell.element || !cell.is_leaf()) continue;
    if (cell.level >= static_cast<int>(counts.size())) counts.resize(cell.level + 1, 0);
    ++counts[cell.level];
  }
  return counts;
}

}  // namespace tensormass
