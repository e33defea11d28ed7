// The leaf mesh of a hierarchy: transition cells, node and cell compaction,
// the leaf mesh's blocks and groups, and the transfer from the previous one
// (see hierarchical_mesh.hpp).
#include <algorithm>
#include <stdexcept>
#include <string>

#include "refinement/node_pairs.hpp"
#include "tensormass/refinement/hierarchical_mesh.hpp"
#include "tensormass/refinement/transition_patterns.hpp"

namespace tensormass {
namespace {

using detail::edge_key;

/// The cells of one element type in the leaf mesh, in the order they are made.
struct LeafList {
  const tm_element_info* element = nullptr;
  std::vector<int> connectivity;
  std::vector<int> owners;
  std::vector<char> transitions;
};

/// Renumbers the nodes of a map keyed by two nodes; drops entries with a removed node.
void renumber_keys(std::unordered_map<std::uint64_t, int>& map, const std::vector<int>& new_index) {
  std::unordered_map<std::uint64_t, int> renumbered;
  for (const auto& [key, node] : map) {
    const int a = new_index[static_cast<std::size_t>(key >> 32)];
    const int b = new_index[static_cast<std::size_t>(key & 0xffffffffu)];
    const int target = new_index[static_cast<std::size_t>(node)];
    if (a >= 0 && b >= 0 && target >= 0) renumbered.emplace(edge_key(a, b), target);
  }
  map = std::move(renumbered);
}

}  // namespace

LeafTransfer HierarchicalMesh::rebuild() {
  LeafTransfer transfer;
  transfer.old_node_count = old_node_count_;
  transfer.old_cell_count = leaf_.cell_count();
  make_transition_nodes();
  compact_nodes(transfer);
  compact_cells();
  build_leaf_mesh();
  for (int owner : leaf_owners_) transfer.cell_sources.push_back(cell_sources_[owner]);
  return transfer;
}

// --- Transitions ----------------------------------------------------------------------

void HierarchicalMesh::make_transition_nodes() {
  fan_centres_.clear();
  std::vector<FacePiece> pieces;
  for (int cell = 0; cell < hierarchy_size(); ++cell) {
    if (!cells_[cell].element) continue;
    const std::string_view name = cells_[cell].element->name;
    if (!cells_[cell].is_leaf()) {
      if (name != "quad4" && name != "hex8") cells_[cell].centre = -1;  // its children do not use it
      continue;
    }
    if (!has_hanging_nodes(cells_[cell]) || name == "tri3") {
      cells_[cell].centre = -1;  // its node, no longer used, goes in compact_nodes
      continue;
    }
    centre_node(cell);
    if (original_.dim == 2) continue;
    for (int f = 0; f < cells_[cell].element->face_count; ++f) face_pieces(face_corners(cells_[cell], f), pieces, true);
  }
}

void HierarchicalMesh::face_pieces(std::span<const int> face, std::vector<FacePiece>& pieces, bool make_centres) {
  const int n = static_cast<int>(face.size());
  std::array<int, 4> corners{-1, -1, -1, -1}, midpoints{-1, -1, -1, -1};
  for (int k = 0; k < n; ++k) {
    corners[k] = face[k];
    midpoints[k] = find_midpoint(face[k], face[(k + 1) % n]);
  }
  const int split = static_cast<int>(std::count_if(midpoints.begin(), midpoints.end(), [](int m) { return m >= 0; }));
  const auto [c0, c1, c2, c3] = corners;
  const auto [m0, m1, m2, m3] = midpoints;
  if (split == 0) {
    pieces.push_back(corners);
    return;
  }
  if (n == 3) {
    if (split == 3) {  // the cell across is split, or all three edges are: red, deeper splits inside
      for (const std::array<int, 3>& t : {std::array<int, 3>{c0, m0, m2}, {m0, c1, m1}, {m2, m1, c2}, {m0, m1, m2}})
        face_pieces(t, pieces, make_centres);
      return;
    }
    for (const Triangle& t : triangle_transition(std::span<const int, 3>(corners.data(), 3),
                                                 std::span<const int, 3>(midpoints.data(), 3), positions_))
      pieces.push_back({t[0], t[1], t[2], -1});
    return;
  }
  int centre = find_face_centre(corners);
  if (centre >= 0 && corner_uses_[centre] > 0) {  // a cell of this face is split: its four quarters
    if (split != 4) throw std::logic_error("hierarchical mesh: a split quad face with a whole edge");
    for (const std::array<int, 4>& q :
         {std::array<int, 4>{c0, m0, centre, m3}, {m0, c1, m1, centre}, {centre, m1, c2, m2}, {m3, centre, m2, c3}})
      face_pieces(q, pieces, make_centres);
    return;
  }
  if (centre < 0) {
    if (!make_centres) throw std::logic_error("hierarchical mesh: a transition face without its centre node");
    centre = face_centre(corners);
  }
  if (make_centres) fan_centres_.push_back(centre);
  for (const Triangle& t : quad_transition(corners, midpoints, centre)) pieces.push_back({t[0], t[1], t[2], -1});
}

// --- Nodes and cells kept --------------------------------------------------------------

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
  for (int node : fan_centres_) keep[node] = 1;
  fan_centres_.clear();
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
  renumber_keys(midpoints_, new_index);
  renumber_keys(face_centres_, new_index);
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

// --- The leaf mesh ---------------------------------------------------------------------

void HierarchicalMesh::build_leaf_mesh() {
  std::vector<LeafList> lists;
  for (const ElementBlock& block : original_.blocks) lists.push_back({block.element, {}, {}, {}});
  for (const tm_element_info* element : transition_elements_)
    if (std::none_of(lists.begin(), lists.end(), [&](const LeafList& list) { return list.element == element; }))
      lists.push_back({element, {}, {}, {}});
  const auto list_of = [&](const tm_element_info* element) -> LeafList& {
    return *std::find_if(lists.begin(), lists.end(), [&](const LeafList& list) { return list.element == element; });
  };
  const auto add = [&](const tm_element_info* element, std::span<const int> nodes, int owner, char transition) {
    LeafList& list = list_of(element);
    list.connectivity.insert(list.connectivity.end(), nodes.begin(), nodes.end());
    list.owners.push_back(owner);
    list.transitions.push_back(transition);
  };
  std::vector<FacePiece> pieces;
  const auto emit = [&](int cell) {
    const HierarchyCell& leaf = cells_[cell];
    if (!has_hanging_nodes(leaf)) {
      add(leaf.element, std::span<const int>(leaf.corners.data(), static_cast<std::size_t>(leaf.corner_count())), cell,
          0);
      return;
    }
    if (original_.dim == 2) {
      const std::array<int, 4> hanging = hanging_midpoints(leaf);
      const std::vector<Triangle> triangles =
          leaf.corner_count() == 4 ? quad_transition(std::span<const int, 4>(leaf.corners.data(), 4),
                                                     std::span<const int, 4>(hanging), leaf.centre)
                                   : triangle_transition(std::span<const int, 3>(leaf.corners.data(), 3),
                                                         std::span<const int, 3>(hanging.data(), 3), positions_);
      for (const Triangle& triangle : triangles) add(transition_elements_[0], triangle, cell, 1);
      return;
    }
    pieces.clear();
    for (int f = 0; f < leaf.element->face_count; ++f) face_pieces(face_corners(leaf, f), pieces, false);
    for (const FacePiece& piece : pieces)
      add(transition_elements_[piece[3] < 0 ? 0 : 1], cone(piece, leaf.centre), cell, 1);
  };
  // Depth first from each original cell, children in order.
  std::vector<int> stack;
  const int original_cells = original_.cell_count();
  for (int root = 0; root < original_cells; ++root) {
    stack.push_back(root);
    while (!stack.empty()) {
      const int cell = stack.back();
      stack.pop_back();
      const HierarchyCell& at = cells_[cell];
      if (at.is_leaf()) emit(cell);
      else
        stack.insert(stack.end(), at.children.rbegin() + static_cast<long>(at.children.size()) - at.child_count(),
                     at.children.rend());
    }
  }
  leaf_ = Mesh{};
  leaf_.dim = original_.dim;
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

// --- Groups ------------------------------------------------------------------------------

void HierarchicalMesh::add_leaf_groups() {
  const int node_count = leaf_.node_count();
  for (const Group& group : original_.groups) {
    Group leaf_group{group.name, group.dim, {}, {}, {}};
    std::vector<char> member(static_cast<std::size_t>(node_count), 0);
    for (int node : group.nodes) member[node] = 1;
    // Nodes are made after the nodes they are the mean of, so one pass in order decides.
    for (int node = original_nodes_; node < node_count; ++node) {
      const NodeParents& parents = node_parents_[node];
      member[node] = parents.count >= 2 && std::all_of(parents.nodes.begin(), parents.nodes.begin() + parents.count,
                                                       [&](int parent) { return parent >= 0 && member[parent]; });
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
    add_facet_pieces(group, leaf_group.facets);
    leaf_.groups.push_back(std::move(leaf_group));
  }
}

void HierarchicalMesh::add_facet_pieces(const Group& group, FacetSet& facets) {
  const auto add = [&](std::span<const int> nodes, int order) {
    facets.nodes.insert(facets.nodes.end(), nodes.begin(), nodes.end());
    facets.offsets.push_back(static_cast<int>(facets.nodes.size()));
    facets.orders.push_back(order);
  };
  const auto add_line = [&](auto& self, int a, int b, int order) -> void {
    if (const int m = find_midpoint(a, b); m >= 0) {
      self(self, a, m, order);
      self(self, m, b, order);
      return;
    }
    add(std::array<int, 2>{a, b}, order);
  };
  std::vector<FacePiece> pieces;
  for (int f = 0; f < group.facets.count(); ++f) {
    const int first = group.facets.offsets[f];
    const int size = group.facets.offsets[f + 1] - first;
    const int order = f < static_cast<int>(group.facets.orders.size()) ? group.facets.orders[f] : 1;
    if (size == 2) {
      add_line(add_line, group.facets.nodes[first], group.facets.nodes[first + 1], order);
      continue;
    }
    pieces.clear();
    face_pieces(std::span<const int>(group.facets.nodes.data() + first, static_cast<std::size_t>(size)), pieces, false);
    for (const FacePiece& piece : pieces) add(std::span<const int>(piece.data(), piece[3] < 0 ? 3u : 4u), order);
  }
}

}  // namespace tensormass
