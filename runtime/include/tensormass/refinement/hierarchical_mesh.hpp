/// \file hierarchical_mesh.hpp
/// A mesh that is refined and coarsened while a simulation runs, and the
/// conforming mesh of its leaves to simulate: 2D meshes of quad4 and tri3
/// cells, 3D meshes of hex8, tet4, prism6 and pyramid5 cells (the beam
/// generator's grids and the meshes of `tensormass mesh`).
///
/// Glossary:
///   hierarchy cell  an original cell (level 0) or a child made by splitting
///                   a cell (level = parent's level + 1); it keeps its
///                   parent and its children
///   leaf            a hierarchy cell without children
///   leaf mesh       the Mesh of the leaves: a leaf with no hanging node is
///                   one cell; a leaf with some is filled by temporary
///                   transition cells (transition_patterns.hpp), dropped and
///                   rebuilt on the next change
///   hanging node    the midpoint of a leaf's edge, or the centre of its
///                   face, made by a neighbour that was split
///
/// Splitting (one level, split_patterns.hpp): tri3, quad4 -> 4 children;
/// tet4, prism6, hex8 -> 8; pyramid5 -> 6 pyramids and 4 tets. A tet's inner octahedron is cut along its
/// shortest diagonal (ties: the first). Children keep the parent's
/// orientation.
///
/// Transitions: in 2D a quad with hanging midpoints is a fan of triangles
/// around its centre, a triangle is cut red-green. In 3D a leaf with hanging
/// nodes is filled by cones from its centre (the mean of its corners) to
/// the pieces of its faces: a quad face split by the neighbour across gives
/// its 4 quarters, one with some split edges a fan of triangles around its
/// centre node (shared with the cell across), a triangle face its red-green
/// pattern; the cones are tet4 over triangles and pyramid5 over quads. Both
/// cells of a face cut it alike, so the leaf mesh conforms.
///
/// 2:1 balance: leaves that share a stretch of edge differ by at most one
/// level (in 3D also across the inner triangle of a red-refined face).
/// Refining splits the marked leaves, then every leaf an edge of which has
/// been split twice on the other side, until none is left. Coarsening
/// merges the children of a parent back into it when all of them are
/// marked leaves and the parent's edges are split at most once by its
/// neighbours; one level per call.
///
/// Nodes: the original nodes first, in their order, then the nodes made by
/// splitting (and transition centres), in the order they were made; a node
/// no cell uses any more is removed (the later ones move down). Coarsening
/// everything back therefore restores the original mesh bit for bit:
/// nodes, cells (original blocks and order), groups.
///
/// Groups of the leaf mesh: a node group gains a new node when all the
/// nodes it is the mean of belong to it (a fixed boundary stays fixed); a
/// group with cells gains the children and transition cells of its cells
/// and their new nodes; a boundary facet (line2 in 2D, tri3 or quad4 in 3D)
/// is replaced by the pieces the leaves cut it into, in its orientation.
#ifndef TENSORMASS_REFINEMENT_HIERARCHICAL_MESH_HPP
#define TENSORMASS_REFINEMENT_HIERARCHICAL_MESH_HPP

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <unordered_map>
#include <vector>

#include "tensormass/kernels/kernel_abi.h"
#include "tensormass/mesh/mesh.hpp"
#include "tensormass/refinement/leaf_transfer.hpp"
#include "tensormass/refinement/transition_patterns.hpp"

namespace tensormass {

/// One cell of the hierarchy.
struct HierarchyCell {
  const tm_element_info* element = nullptr;  ///< nullptr for a removed cell (internal)
  /// Node indices in the element's order (2D: counter-clockwise), -1 after the last.
  std::array<int, 8> corners{-1, -1, -1, -1, -1, -1, -1, -1};
  int parent = -1;  ///< -1 for an original cell
  int level = 0;    ///< 0 for an original cell
  /// All -1 for a leaf; up to 10 (a pyramid5's), -1 after the last.
  std::array<int, 10> children{-1, -1, -1, -1, -1, -1, -1, -1, -1, -1};
  int origin = 0;  ///< the original cell (mesh-wide index in the wrapped mesh) this cell lies in
  /// Its centre node while a transition fills it or (quad4, hex8) its
  /// children use it, else -1.
  int centre = -1;

  int corner_count() const {
    return static_cast<int>(std::count_if(corners.begin(), corners.end(), [](int n) { return n >= 0; }));
  }
  int child_count() const {
    return static_cast<int>(std::count_if(children.begin(), children.end(), [](int c) { return c >= 0; }));
  }
  bool is_leaf() const { return children[0] < 0; }
};

class HierarchicalMesh {
 public:
  static constexpr int kUnlimited = std::numeric_limits<int>::max();

  /// Wraps `original`: a valid 2D mesh of quad4 and tri3 cells or 3D mesh
  /// of hex8, tet4, prism6 and pyramid5 cells, each of positive area (volume), every
  /// edge (face) shared by at most two cells, group facets of the mesh's
  /// facet kinds (line2; tri3, quad4). Throws InputError otherwise.
  explicit HierarchicalMesh(Mesh original);

  /// The conforming mesh of the leaves (see the file comment).
  const Mesh& leaf_mesh() const { return leaf_; }
  /// leaf_mesh().cell_count(): the hierarchy cell each leaf-mesh cell is,
  /// or fills (a transition cell).
  std::span<const int> leaf_owners() const { return leaf_owners_; }
  /// leaf_mesh().cell_count(): the level of each leaf-mesh cell's owner.
  std::span<const int> leaf_levels() const { return leaf_levels_; }
  /// leaf_mesh().cell_count(): 1 for a transition cell, 0 for a whole leaf.
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
    std::array<int, 8> nodes{-1, -1, -1, -1, -1, -1, -1, -1};
    int count = 0;  ///< 0 original node, 2 edge midpoint, 4 face (quad) centre, up to 8 cell centre
  };

  // Hierarchy edits (hierarchical_mesh.cpp).
  void add_original_cells();
  int add_node(const NodeParents& parents);
  int find_midpoint(int a, int b) const;
  int midpoint(int a, int b);
  int find_face_centre(std::span<const int> face) const;
  int face_centre(std::span<const int> face);
  int centre_node(int cell);
  void add_cell(const HierarchyCell& cell);
  int tet_diagonal(const HierarchyCell& cell);
  void split(int cell);
  void merge(int parent);
  bool split_twice(const HierarchyCell& cell) const;
  void balance();
  std::vector<int> marked_owners(std::span<const int> marked_cells, const char* operation) const;
  std::array<int, 4> hanging_midpoints(const HierarchyCell& leaf) const;
  bool has_hanging_nodes(const HierarchyCell& leaf) const;
  /// Corners of face f of a cell (3 or 4, counter-clockwise seen from outside).
  std::vector<int> face_corners(const HierarchyCell& cell, int f) const;

  // Leaf mesh and transfer (hierarchical_leaf_mesh.cpp).
  LeafTransfer rebuild();
  void make_transition_nodes();
  /// The pieces a 3D face (3 or 4 corners) is cut into by the leaves on
  /// both sides; with `make_centres`, makes missing fan centres and lists them.
  void face_pieces(std::span<const int> face, std::vector<FacePiece>& pieces, bool make_centres);
  void compact_nodes(LeafTransfer& transfer);
  void compact_cells();
  void build_leaf_mesh();
  void add_leaf_groups();
  void add_facet_pieces(const Group& group, FacetSet& facets);
  void expand_node(int node, double weight, std::vector<std::pair<int, double>>& sources) const;

  Mesh original_;
  /// Element types transition cells are made of (2D: tri3; 3D: tet4, pyramid5).
  std::vector<const tm_element_info*> transition_elements_;
  int original_nodes_ = 0;
  std::vector<double> positions_;                     ///< node count by 3
  std::vector<NodeParents> node_parents_;             ///< node count
  std::vector<int> corner_uses_;                      ///< node count: live hierarchy cells with the node as a corner
  std::unordered_map<std::uint64_t, int> midpoints_;  ///< edge (low, high node) -> its midpoint node
  /// 3D quad face (its lowest corner, the corner opposite) -> its centre node.
  std::unordered_map<std::uint64_t, int> face_centres_;
  std::vector<int> fan_centres_;  ///< during a rebuild: face centres the transitions need
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
