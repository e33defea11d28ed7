/// \file transition_patterns.hpp
/// Temporary triangles that fill a 2D leaf cell whose edges carry hanging
/// midpoints (the midpoint of an edge that the neighbour across it has
/// split), so that the mesh of the leaves stays conforming.
///
/// Edge k of a cell joins its corners k and k+1 (modulo the corner count),
/// as in the quad4 and tri3 reference elements. Corners are counter-clockwise
/// and so is every triangle returned, (3 nodes each).
///
///   quad4  a fan around the quad's centre node: two triangles on each
///          split edge (corner, midpoint, centre), (midpoint, corner,
///          centre) and one on each whole edge (corner, corner, centre)
///   tri3   red-green: one split edge, the triangle is bisected from the
///          opposite corner (2 triangles); two split edges, the corner
///          between them is cut off and the rest split along its shorter
///          diagonal (3 triangles, a tie going by node index); three,
///          the four triangles of a red refinement
///
/// In 3D a leaf cell with hanging nodes is filled by cones from its centre
/// node to the pieces of its faces (hierarchical_mesh.hpp says which): a
/// tet4 over a triangle, a pyramid5 over a quad.
#ifndef TENSORMASS_REFINEMENT_TRANSITION_PATTERNS_HPP
#define TENSORMASS_REFINEMENT_TRANSITION_PATTERNS_HPP

#include <array>
#include <span>
#include <vector>

namespace tensormass {

using Triangle = std::array<int, 3>;

/// The fan of a quad (corners: 4 nodes, counter-clockwise) with
/// midpoints[k] the node hanging on edge k, or -1 for a whole edge, around
/// the node `centre`: 4 + (number of split edges) triangles.
std::vector<Triangle> quad_transition(std::span<const int, 4> corners, std::span<const int, 4> midpoints, int centre);

/// The red-green pattern of a triangle (corners: 3 nodes, counter-clockwise)
/// with midpoints[k] the node hanging on edge k, or -1. `positions` holds
/// the nodes' coordinates (node count by 3) for the choice of diagonal.
/// No split edge gives the triangle itself.
std::vector<Triangle> triangle_transition(std::span<const int, 3> corners, std::span<const int, 3> midpoints,
                                          std::span<const double> positions);

/// A piece of a cell's face: 3 nodes (piece[3] = -1) or 4, counter-clockwise
/// seen from outside the cell.
using FacePiece = std::array<int, 4>;

/// The cone from an inner node `apex` to a face piece, in the reference
/// elements' node orders: tet4 (p0, p2, p1, apex) or pyramid5
/// (q0, q3, q2, q1, apex); positive volume when the piece faces away from
/// the apex.
std::vector<int> cone(const FacePiece& piece, int apex);

/// The element types transition cells are made of: tri3 in 2D; tet4 and
/// pyramid5 in 3D.
std::vector<const char*> transition_element_names(int dim);

}  // namespace tensormass

#endif
