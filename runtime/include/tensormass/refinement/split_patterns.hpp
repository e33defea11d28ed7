/// \file split_patterns.hpp
/// How one cell splits into children of its own type, in the cell's local
/// numbering: the nodes of its refined grid, each the mean of some of its
/// corners, and the children as lists of those nodes in the element's
/// corner order (every child has the parent's orientation).
///
///   tri3    4 children over the edge midpoints (red refinement)
///   quad4   4 children over the edge midpoints and the centre
///   tet4    8 children: one at each corner, and the inner octahedron cut
///           into 4 along one of its three diagonals (diagonal 0 joins the
///           midpoints of edges 0-1 and 2-3, 1 those of 0-2 and 1-3, 2
///           those of 0-3 and 1-2)
///   prism6  8 children: the triangles red-refined, in two layers
///   hex8    8 children over the 3 x 3 x 3 grid of corners, edge midpoints,
///           face centres and the centre
///   pyramid5  6 pyramid5 and 4 tet4: a pyramid on each quarter of the
///           base under its lateral edge's midpoint, one at the apex, one
///           upside down from the base's centre, and a tet under the middle
///           triangle of each red-cut side
#ifndef TENSORMASS_REFINEMENT_SPLIT_PATTERNS_HPP
#define TENSORMASS_REFINEMENT_SPLIT_PATTERNS_HPP

#include <array>
#include <string_view>
#include <vector>

namespace tensormass {

/// A node of the refined grid: the mean of `count` local corners. count 1
/// is the corner itself, 2 an edge midpoint, 4 a quad face's centre (in 3D,
/// corners in the face's cyclic order) or a quad4's centre (2D), 8 a
/// hex8's centre.
struct SplitNode {
  std::array<int, 8> corners{-1, -1, -1, -1, -1, -1, -1, -1};
  int count = 0;
};

struct SplitPattern {
  std::vector<SplitNode> nodes;
  /// Per child: indices into nodes, as many as its element has corners.
  std::vector<std::vector<int>> children;
  /// Per child: its element type; empty when every child is of the parent's type.
  std::vector<std::string_view> child_elements;
};

/// The pattern of a first-order element (tri3, quad4, tet4, prism6, hex8, pyramid5);
/// `tet_diagonal` (0, 1 or 2) picks the octahedron's cut for tet4. Throws
/// std::invalid_argument for another element.
const SplitPattern& split_pattern(std::string_view element, int tet_diagonal = 0);

/// Whether the element can be split (has a pattern above).
bool has_split_pattern(std::string_view element);

}  // namespace tensormass

#endif
