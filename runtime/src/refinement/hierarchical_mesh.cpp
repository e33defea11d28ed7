// Refinement, balance, coarsening and the leaf mesh of a 2D hierarchy
// (see hierarchical_mesh.hpp).
#include "tensormass/refinement/hierarchical_mesh.hpp"

#include <algorithm>
#include <string>

#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/mesh/mesh_conformity.hpp"
#include "tensormass/refinement/transition_patterns.hpp"

namespace tensormass {
namespace {

std::uint64_t edge_key(int a, int b) {
  return static_cast<std::uint64_t>(std::min(a, b)) << 32 | static_cast<std::uint32_t>(std::max(a, b));
}

/// Twice the signed area of the polygon `corners` (count nodes) in the x-y plane.
double twice_signed_area(std::span<const double> positions, std::span<const int> corners) {
  double sum = 0;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const double* p = &positions[3 * static_cast<std::size_t>(corners[k])];
    const double* q = &positions[3 * static_cast<std::size_t>(corners[(k + 1) % corners.size()])];
    sum += p[0] * q[1] - q[0] * p[1];
  }
  return sum;
}

std::string mesh_name(const Mesh& mesh) { return mesh.source.empty() ? std::string("mesh") : mesh.source; }

void check_cells(const Mesh& mesh) {
  for (const ElementBlock& block : mesh.blocks) {
    const std::string name = block.element->name;
    if (name != "quad4" && name != "tri3")
      throw InputError(mesh_name(mesh) + ": " + name + " cells cannot be refined (refinement supports quad4 and tri3)");
    for (int local = 0; local < block.count(); ++local)
      if (!(twice_signed_area(mesh.rest_positions, block.cell_nodes(local)) > 0))
        throw InputError(mesh_name(mesh) + ": " + mesh.describe_cell(block.first_cell + local) +
                         " is clockwise or flat; refinement needs counter-clockwise cells of positive area");
  }
}

void check_groups(const Mesh& mesh) {
  for (const Group& group : mesh.groups)
    for (int f = 0; f < group.facets.count(); ++f) {
      const int size = group.facets.offsets[f + 1] - group.facets.offsets[f];
      if (size != 2)
        throw InputError(mesh_name(mesh) + ": group '" + group.name + "' has a facet of " + std::to_string(size) +
                         " nodes; refinement supports line2 facets");
    }
}

/// Throws InputError unless `mesh` is a 2D mesh the hierarchy can wrap.
void check_refinable(const Mesh& mesh) {
  mesh.validate();
  if (mesh.dim != 2)
    throw InputError(mesh_name(mesh) + ": only 2D meshes can be refined, this one is " + std::to_string(mesh.dim) +
                     "D");
  check_cells(mesh);
  check_groups(mesh);
  const ConformityReport conformity = check_conformity(mesh);
  if (conformity.overused_faces > 0)
    throw InputError(mesh_name(mesh) + ": " + std::to_string(conformity.overused_faces) +
                     " edges are shared by more than two cells; refinement needs a conforming mesh");
}

/// The cells of one element type in the leaf mesh, in the order they are made.
struct LeafList {
  const tm_element_info* element = nullptr;
  std::vector<int> connectivity;
  std::vector<int> owners;
  std::vector<char> transitions;
};

}  // namespace

// --- Construction ------------------------------------------------------------------

HierarchicalMesh::HierarchicalMesh(Mesh original) : original_(std::move(original)) {
  check_refinable(original_);
  quad4_ = Registry::instance().element("quad4");
  tri3_ = Registry::instance().element("tri3");
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
  const int node = add_node({{a, b, -1, -1}, 2});
  midpoints_.emplace(edge_key(a, b), node);
  return node;
}

int HierarchicalMesh::centre_node(int cell) {
  if (cells_[cell].centre < 0) cells_[cell].centre = add_node({cells_[cell].corners, 4});
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

// --- Refinement ---------------------------------------------------------------------

void HierarchicalMesh::split(int cell) {
  const int n = cells_[cell].corner_count();
  std::array<int, 4> m{-1, -1, -1, -1};
  for (int k = 0; k < n; ++k) m[k] = midpoint(cells_[cell].corners[k], cells_[cell].corners[(k + 1) % n]);
  const std::array<int, 4> c = cells_[cell].corners;
  std::array<std::array<int, 4>, 4> children{};
  if (n == 4) {
    const int z = centre_node(cell);
    children = {{{c[0], m[0], z, m[3]}, {m[0], c[1], m[1], z}, {z, m[1], c[2], m[2]}, {m[3], z, m[2], c[3]}}};
  } else {
    children = {{{c[0], m[0], m[2], -1}, {m[0], c[1], m[1], -1}, {m[2], m[1], c[2], -1}, {m[0], m[1], m[2], -1}}};
  }
  for (int k = 0; k < 4; ++k) {
    HierarchyCell child;
    child.element = cells_[cell].element;
    child.corners = children[k];
    child.parent = cell;
    child.level = cells_[cell].level + 1;
    child.origin = cells_[cell].origin;
    add_cell(child);
    cells_[cell].children[k] = hierarchy_size() - 1;
    cell_sources_.back() = cell_sources_[cell];
  }
}

bool HierarchicalMesh::needs_balance(int leaf) const {
  const HierarchyCell& cell = cells_[leaf];
  const int n = cell.corner_count();
  for (int k = 0; k < n; ++k) {
    const int a = cell.corners[k], b = cell.corners[(k + 1) % n];
    const int m = find_midpoint(a, b);
    if (m >= 0 && (find_midpoint(a, m) >= 0 || find_midpoint(m, b) >= 0)) return true;
  }
  return false;
}

void HierarchicalMesh::balance() {
  for (bool changed = true; changed;) {
    changed = false;
    for (int cell = 0; cell < hierarchy_size(); ++cell)
      if (cells_[cell].element && cells_[cell].is_leaf() && needs_balance(cell)) {
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

bool HierarchicalMesh::can_merge(int parent) const {
  const HierarchyCell& cell = cells_[parent];
  const int n = cell.corner_count();
  for (int k = 0; k < n; ++k) {
    const int a = cell.corners[k], b = cell.corners[(k + 1) % n];
    const int m = find_midpoint(a, b);
    if (find_midpoint(a, m) >= 0 || find_midpoint(m, b) >= 0) return false;  // split twice by the neighbour
  }
  return true;
}

void HierarchicalMesh::merge(int parent) {
  HierarchyCell& cell = cells_[parent];
  cell_sources_[parent] = cell_sources_[cell.children[0]];
  for (int child : cell.children) {
    HierarchyCell& removed = cells_[child];
    for (int k = 0; k < removed.corner_count(); ++k) --corner_uses_[removed.corners[k]];
    removed.element = nullptr;
  }
  cell.children = {-1, -1, -1, -1};
  const int n = cell.corner_count();
  for (int k = 0; k < n; ++k) {
    const std::uint64_t key = edge_key(cell.corners[k], cell.corners[(k + 1) % n]);
    if (corner_uses_[midpoints_.at(key)] == 0) midpoints_.erase(key);  // the neighbour has not split it
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
    return std::all_of(cells_[parent].children.begin(), cells_[parent].children.end(), [&](int child) {
      return cells_[child].is_leaf() && std::binary_search(owners.begin(), owners.end(), child);
    });
  };
  parents.erase(std::remove_if(parents.begin(), parents.end(), [&](int p) { return !all_marked_leaves(p); }),
                parents.end());
  // Deepest first, so that a neighbour merged in the same call no longer blocks.
  std::stable_sort(parents.begin(), parents.end(), [&](int p, int q) { return cells_[p].level > cells_[q].level; });
  for (int parent : parents)
    if (can_merge(parent)) merge(parent);
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

// --- Leaf mesh ----------------------------------------------------------------------

LeafTransfer HierarchicalMesh::rebuild() {
  LeafTransfer transfer;
  transfer.old_node_count = old_node_count_;
  transfer.old_cell_count = leaf_.cell_count();
  for (int cell = 0; cell < hierarchy_size(); ++cell) {
    const HierarchyCell& leaf = cells_[cell];
    if (!leaf.element || !leaf.is_leaf() || leaf.corner_count() != 4) continue;
    const std::array<int, 4> hanging = hanging_midpoints(leaf);
    if (std::any_of(hanging.begin(), hanging.end(), [](int m) { return m >= 0; })) centre_node(cell);
    else cells_[cell].centre = -1;  // its node, no longer used, goes below
  }
  compact_nodes(transfer);
  compact_cells();
  build_leaf_mesh();
  for (int owner : leaf_owners_) transfer.cell_sources.push_back(cell_sources_[owner]);
  return transfer;
}

void HierarchicalMesh::expand_node(int node, double weight, std::vector<std::pair<int, double>>& sources) const {
  if (node < old_node_count_) {
    sources.emplace_back(node, weight);
    return;
  }
  const NodeParents& parents = node_parents_[node];
  for (int k = 0; k < parents.count; ++k) expand_node(parents.nodes[k], weight / parents.count, sources);
}

void HierarchicalMesh::compact_nodes(LeafTransfer& transfer) {
  const int count = static_cast<int>(node_parents_.size());
  std::vector<char> keep(static_cast<std::size_t>(count), 0);
  for (int node = 0; node < count; ++node) keep[node] = corner_uses_[node] > 0;
  for (const HierarchyCell& cell : cells_)
    if (cell.element && cell.centre >= 0) keep[cell.centre] = 1;
  std::vector<int> new_index(static_cast<std::size_t>(count), -1);
  int kept = 0;
  for (int node = 0; node < count; ++node) {
    if (!keep[node]) continue;
    new_index[node] = kept++;
    std::vector<std::pair<int, double>> sources;
    expand_node(node, 1.0, sources);
    for (const auto& [source, weight] : sources) {
      transfer.node_sources.push_back(source);
      transfer.node_weights.push_back(weight);
    }
    transfer.node_offsets.push_back(static_cast<int>(transfer.node_sources.size()));
  }
  for (int node = 0; node < count; ++node) {
    const int target = new_index[node];
    if (target < 0 || target == node) continue;
    std::copy_n(positions_.begin() + 3 * static_cast<std::ptrdiff_t>(node), 3,
                positions_.begin() + 3 * static_cast<std::ptrdiff_t>(target));
    node_parents_[target] = node_parents_[node];
    corner_uses_[target] = corner_uses_[node];
  }
  positions_.resize(3 * static_cast<std::size_t>(kept));
  node_parents_.resize(kept);
  corner_uses_.resize(kept);
  const auto renumber = [&](int node) { return node < 0 ? -1 : new_index[node]; };
  for (NodeParents& parents : node_parents_)
    for (int k = 0; k < parents.count; ++k) parents.nodes[k] = renumber(parents.nodes[k]);
  for (HierarchyCell& cell : cells_) {
    for (int& corner : cell.corners) corner = renumber(corner);
    cell.centre = renumber(cell.centre);
  }
  std::unordered_map<std::uint64_t, int> midpoints;
  for (const auto& [key, node] : midpoints_) {
    const int a = renumber(static_cast<int>(key >> 32)), b = renumber(static_cast<int>(key & 0xffffffffu));
    if (a >= 0 && b >= 0 && renumber(node) >= 0) midpoints.emplace(edge_key(a, b), renumber(node));
  }
  midpoints_ = std::move(midpoints);
}

void HierarchicalMesh::compact_cells() {
  std::vector<int> new_index(cells_.size(), -1);
  int kept = 0;
  for (std::size_t cell = 0; cell < cells_.size(); ++cell)
    if (cells_[cell].element) new_index[cell] = kept++;
  const auto renumber = [&](int cell) { return cell < 0 ? -1 : new_index[cell]; };
  for (std::size_t cell = 0; cell < cells_.size(); ++cell) {
    if (new_index[cell] < 0) continue;
    HierarchyCell moved = cells_[cell];
    moved.parent = renumber(moved.parent);
    for (int& child : moved.children) child = renumber(child);
    cells_[new_index[cell]] = moved;
    cell_sources_[new_index[cell]] = cell_sources_[cell];
  }
  cells_.resize(kept);
  cell_sources_.resize(kept);
}

void HierarchicalMesh::build_leaf_mesh() {
  std::vector<LeafList> lists;
  for (const ElementBlock& block : original_.blocks) lists.push_back({block.element, {}, {}, {}});
  for (const tm_element_info* element : {quad4_, tri3_})
    if (std::none_of(lists.begin(), lists.end(), [&](const LeafList& list) { return list.element == element; }))
      lists.push_back({element, {}, {}, {}});
  const auto list_of = [&](const tm_element_info* element) -> LeafList& {
    return *std::find_if(lists.begin(), lists.end(), [&](const LeafList& list) { return list.element == element; });
  };
  const auto emit = [&](int cell) {
    const HierarchyCell& leaf = cells_[cell];
    const std::array<int, 4> hanging = hanging_midpoints(leaf);
    const bool whole = std::none_of(hanging.begin(), hanging.end(), [](int m) { return m >= 0; });
    if (whole) {
      LeafList& list = list_of(leaf.element);
      list.connectivity.insert(list.connectivity.end(), leaf.corners.begin(),
                               leaf.corners.begin() + leaf.corner_count());
      list.owners.push_back(cell);
      list.transitions.push_back(0);
      return;
    }
    const std::vector<Triangle> triangles =
        leaf.corner_count() == 4
            ? quad_transition(std::span<const int, 4>(leaf.corners), std::span<const int, 4>(hanging), leaf.centre)
            : triangle_transition(std::span<const int, 3>(leaf.corners.data(), 3),
                                  std::span<const int, 3>(hanging.data(), 3), positions_);
    LeafList& list = list_of(tri3_);
    for (const Triangle& triangle : triangles) {
      list.connectivity.insert(list.connectivity.end(), triangle.begin(), triangle.end());
      list.owners.push_back(cell);
      list.transitions.push_back(1);
    }
  };
  // Depth first from each original cell, children in order.
  std::vector<int> stack;
  const int original_cells = original_.cell_count();
  for (int root = 0; root < original_cells; ++root) {
    stack.push_back(root);
    while (!stack.empty()) {
      const int cell = stack.back();
      stack.pop_back();
      if (cells_[cell].is_leaf()) emit(cell);
      else stack.insert(stack.end(), cells_[cell].children.rbegin(), cells_[cell].children.rend());
    }
  }
  leaf_ = Mesh{};
  leaf_.dim = 2;
  leaf_.source = original_.source;
  leaf_.rest_positions = positions_;
  if (!original_.node_source_ids.empty()) {
    leaf_.node_source_ids.assign(original_.node_source_ids.begin(), original_.node_source_ids.end());
    const long first_new = 1 + *std::max_element(original_.node_source_ids.begin(), original_.node_source_ids.end());
    for (int node = original_nodes_; node < leaf_.node_count(); ++node)
      leaf_.node_source_ids.push_back(first_new + (node - original_nodes_));
  }
  const bool cell_ids = std::all_of(original_.blocks.begin(), original_.blocks.end(), [](const ElementBlock& block) {
    return static_cast<int>(block.source_ids.size()) == block.count();
  });
  leaf_owners_.clear();
  leaf_levels_.clear();
  leaf_transitions_.clear();
  first_leaf_cell_.assign(cells_.size(), -1);
  for (LeafList& list : lists) {
    if (list.owners.empty()) continue;
    ElementBlock block{list.element, std::move(list.connectivity), {}, leaf_.cell_count()};
    for (std::size_t local = 0; local < list.owners.size(); ++local) {
      const int owner = list.owners[local];
      if (cell_ids) {
        const auto [b, origin_local] = original_.locate(cells_[owner].origin);
        block.source_ids.push_back(original_.blocks[b].source_ids[origin_local]);
      }
      if (first_leaf_cell_[owner] < 0) first_leaf_cell_[owner] = block.first_cell + static_cast<int>(local);
      leaf_owners_.push_back(owner);
      leaf_levels_.push_back(cells_[owner].level);
      leaf_transitions_.push_back(list.transitions[local]);
    }
    leaf_.blocks.push_back(std::move(block));
  }
  add_leaf_groups();
  leaf_.validate();
}

void HierarchicalMesh::add_leaf_groups() {
  const int node_count = leaf_.node_count();
  for (const Group& group : original_.groups) {
    Group leaf_group{group.name, group.dim, {}, {}, {}};
    std::vector<char> member(static_cast<std::size_t>(node_count), 0);
    for (int node : group.nodes) member[node] = 1;
    for (int node = original_nodes_; node < node_count; ++node) {
      const NodeParents& parents = node_parents_[node];
      member[node] = parents.count == 2 && parents.nodes[0] >= 0 && parents.nodes[1] >= 0 && member[parents.nodes[0]] &&
                     member[parents.nodes[1]];
    }
    for (int cell = 0; cell < static_cast<int>(leaf_owners_.size()); ++cell) {
      if (!std::binary_search(group.cells.begin(), group.cells.end(), cells_[leaf_owners_[cell]].origin)) continue;
      leaf_group.cells.push_back(cell);
      const auto [b, local] = leaf_.locate(cell);
      for (int node : leaf_.blocks[b].cell_nodes(local))
        if (node >= original_nodes_) member[node] = 1;
    }
    for (int node = 0; node < node_count; ++node)
      if (member[node]) leaf_group.nodes.push_back(node);
    FacetSet& facets = leaf_group.facets;
    const auto add_piece = [&](auto& self, int a, int b, int order) -> void {
      if (const int m = find_midpoint(a, b); m >= 0) {
        self(self, a, m, order);
        self(self, m, b, order);
        return;
      }
      facets.nodes.push_back(a);
      facets.nodes.push_back(b);
      facets.offsets.push_back(static_cast<int>(facets.nodes.size()));
      facets.orders.push_back(order);
    };
    for (int f = 0; f < group.facets.count(); ++f) {
      const int first = group.facets.offsets[f];
      const int order = f < static_cast<int>(group.facets.orders.size()) ? group.facets.orders[f] : 1;
      add_piece(add_piece, group.facets.nodes[first], group.facets.nodes[first + 1], order);
    }
    leaf_.groups.push_back(std::move(leaf_group));
  }
}

}  // namespace tensormass
