/// \file hierarchical_mesh.hpp
/// A 2D mesh of quad4 and tri3 cells that is refined and coarsened while a
/// simulation runs, and the conforming mesh of its leaves to simulate.
///
/// Glossary:
///   hierarchy cell  an original cell (level 0) or a child made by splitting
///                   a cell (level = parent's level + 1); it keeps its
///                   parent and its four children
///   leaf            a hierarchy cell without children
///   leaf mesh       the Mesh of the leaves: a leaf with no hanging midpoint
///                   on its edges is one cell; a leaf with some is filled by
///                   temporary transition triangles (transition_patterns.hpp),
///                   dropped and rebuilt on the next change
///   hanging midpoint the midpoint of a leaf's edge, made by the neighbour
///                   across that edge when it was split
///
/// Splitting (one level): quad -> 4 quads over the edge midpoints and the
/// centre (the mean of the corners), child k holding the parent's corner k;
/// tri -> 4 tris over the edge midpoints, child k (k < 3) holding corner k,
/// child 3 in the middle. Cells stay counter-clockwise.
///
/// 2:1 balance: leaves that share a stretch of edge differ by at most one
/// level. Refining splits the marked leaves, then every leaf an edge of
/// which has been split twice on the other side, until none is left.
/// Coarsening merges the children of a parent back into it when all of
/// them are marked leaves and the parent's edges are split at most once by
/// its neighbours; one level per call.
///
/// Nodes: the original nodes first, in their order, then the nodes made by
/// splitting (and transition centres), in the order they were made; a node
/// no cell uses any more is removed (the later ones move down). Coarsening
/// everything back therefore restores the original mesh bit for bit:
/// nodes, cells (original blocks and order), groups.
///
/// Groups of the leaf mesh: a node group gains an edge midpoint when both
/// ends of the edge belong to it (a fixed boundary stays fixed); a group
/// with cells gains the children and transition triangles of its cells and
/// their new nodes; a boundary facet (line2) is replaced by the pieces its
/// edge is split into, in its direction.
#ifndef TENSORMASS_REFINEMENT_HIERARCHICAL_MESH_HPP
#define TENSORMASS_REFINEMENT_HIERARCHICAL_MESH_HPP

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <unordered_map>
#include <vector>

#include "tensormass/kernels/kernel_abi.h"
#include "tensormass/mesh/mesh.hpp"
#include "tensormass/refinement/leaf_transfer.hpp"

namespace tensormass {

/// One cell of the hierarchy.
struct HierarchyCell {
  const tm_element_info* element = nullptr;     ///< quad4 or tri3; nullptr for a removed cell (internal)
  std::array<int, 4> corners{-1, -1, -1, -1};   ///< counter-clockwise node indices; corners[3] = -1 for tri3
  int parent = -1;                              ///< -1 for an original cell
  int level = 0;                                ///< 0 for an original cell
  std::array<int, 4> children{-1, -1, -1, -1};  ///< all -1 for a leaf
  int origin = 0;   ///< the original cell (mesh-wide index in the wrapped mesh) this cell lies in
  int centre = -1;  ///< quad4: its centre node while it has children or a transition, else -1

  int corner_count() const { return corners[3] < 0 ? 3 : 4; }
  bool is_leaf() const { return children[0] < 0; }
};

class HierarchicalMesh {
 public:
  static constexpr int kUnlimited = std::numeric_limits<int>::max();

  /// Wraps `original`: a valid 2D mesh of quad4 and tri3 cells, each with a
  /// positive area, every edge shared by at most two cells, group facets of
  /// two nodes (line2). Throws InputError otherwise.
  explicit HierarchicalMesh(Mesh original);

  /// The conforming mesh of the leaves (see the file comment).
  const Mesh& leaf_mesh() const { return leaf_; }
  /// leaf_mesh().cell_count(): the hierarchy cell each leaf-mesh cell is,
  /// or fills (a transition triangle).
  std::span<const int> leaf_owners() const { return leaf_owners_; }
  /// leaf_mesh().cell_count(): the level of each leaf-mesh cell's owner.
  std::span<const int> leaf_levels() const { return leaf_levels_; }
  /// leaf_mesh().cell_count(): 1 for a transition triangle, 0 for a whole leaf.
  std::span<const char> leaf_transitions() const { return leaf_transitions_; }

  /// Splits the owners of the marked leaf-mesh cells (indices into
  /// leaf_mesh(), repeats allowed) whose level is below max_level, and the
  /// leaves 2:1 balance needs, then rebuilds the leaf mesh. Returns how to
  /// carry fields from the previous leaf mesh to the new one. Throws
  /// InputError for an index outside the leaf mesh or a negative max_level.
  LeafTransfer refine(std::span<const int> marked_cells, int max_level = kUnlimited);
  /// Merges back each parent all of whose children are leaves owning a
  /// marked leaf-mesh cell, where balance allows (see the file comment);
  /// rebuilds the leaf mesh. Throws InputError for an index outside it.
  LeafTransfer coarsen(std::span<const int> marked_cells);

  int hierarchy_size() const { return static_cast<int>(cells_.size()); }
  const HierarchyCell& hierarchy_cell(int cell) const { return cells_.at(static_cast<std::size_t>(cell)); }
  /// The wrapped mesh, as given.
  const Mesh& original_mesh() const { return original_; }
  /// Number of leaves per level, from level 0 to the deepest level.
  std::vector<int> leaves_per_level() const;

 private:
  /// How a node was made: its value is the mean of these nodes' values.
  struct NodeParents {
    std::array<int, 4> nodes{-1, -1, -1, -1};
    int count = 0;  ///< 0 original node, 2 edge midpoint, 4 quad centre
  };

  // Hierarchy edits.
  void add_original_cells();
  int add_node(const NodeParents& parents);
  int find_midpoint(int a, int b) const;
  int midpoint(int a, int b);
  int centre_node(int cell);
  void add_cell(const HierarchyCell& cell);
  void split(int cell);
  void merge(int parent);
  bool needs_balance(int leaf) const;
  bool can_merge(int parent) const;
  void balance();
  std::vector<int> marked_owners(std::span<const int> marked_cells, const char* operation) const;
  std::array<int, 4> hanging_midpoints(const HierarchyCell& leaf) const;

  // Leaf mesh and transfer.
  LeafTransfer rebuild();
  void compact_nodes(LeafTransfer& transfer);
  void compact_cells();
  void build_leaf_mesh();
  void add_leaf_groups();
  void expand_node(int node, double weight, std::vector<std::pair<int, double>>& sources) const;

  Mesh original_;
  const tm_element_info* quad4_ = nullptr;
  const tm_element_info* tri3_ = nullptr;
  int original_nodes_ = 0;
  std::vector<double> positions_;                     ///< node count by 3
  std::vector<NodeParents> node_parents_;             ///< node count
  std::vector<int> corner_uses_;                      ///< node count: live hierarchy cells with the node as a corner
  std::unordered_map<std::uint64_t, int> midpoints_;  ///< edge (low, high node) -> its midpoint node
  std::vector<HierarchyCell> cells_;
  std::vector<int> cell_sources_;  ///< hierarchy size: first leaf-mesh cell of the old mesh covering it

  Mesh leaf_;
  std::vector<int> leaf_owners_, leaf_levels_;
  std::vector<char> leaf_transitions_;
  std::vector<int> first_leaf_cell_;  ///< hierarchy size: first leaf-mesh cell it owns, -1 when not a leaf
  int old_node_count_ = 0;            ///< during a change: nodes of the previous leaf mesh
};

}  // namespace tensormass

#endif
