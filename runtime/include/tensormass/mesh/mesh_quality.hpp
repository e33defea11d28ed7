/// \file mesh_quality.hpp
/// Shape quality of mesh cells at rest: scaled Jacobian, edge ratio,
/// inversion and volume, per cell and summarised per element type.
///
/// Definitions (xyz: the cell's node coordinates, nodes by 3, our node order):
///   scaled Jacobian  the minimum over the corner nodes of
///                    det(e1, e2[, e3]) / (|e1| |e2| [|e3|]), where e_k are
///                    the edges leaving the corner towards its neighbours
///                    along the element's edges (ordered as in the reference
///                    element, so a valid cell gives a positive value;
///                    the pyramid apex uses each triple of its four edges),
///                    scaled so that the ideal shape gives 1 (equilateral
///                    triangle, square, regular tetrahedron, cube, right
///                    prism on an equilateral triangle with square sides,
///                    pyramid with all edges equal). Quadratic elements use
///                    their corners. In 2D the x-y plane is used.
///   edge ratio       longest / shortest corner-to-corner edge (>= 1;
///                    infinity for a zero-length edge)
///   inverted         scaled Jacobian <= 0, or det J <= 0 at a point of the
///                    element's default quadrature rule (what a simulation
///                    model rejects)
///   volume           sum over the default quadrature rule of w_q det J_q
///                    (area with unit thickness in 2D); NaN when inverted
///                    at a quadrature point
#ifndef TENSORMASS_MESH_QUALITY_HPP
#define TENSORMASS_MESH_QUALITY_HPP

#include <span>
#include <string>
#include <vector>

#include "tensormass/kernels/kernel_abi.h"
#include "tensormass/mesh/mesh.hpp"

namespace tensormass {

/// Quality of one cell.
struct CellQuality {
  double scaled_jacobian = 0;  ///< 1 for the ideal shape, <= 0 inverted or flat
  double edge_ratio = 0;       ///< >= 1
  bool inverted = false;       ///< at a corner or a quadrature point
  double volume = 0;           ///< area in 2D; NaN when inverted at a quadrature point
};

/// Summary over the cells of one element type.
struct ElementTypeQuality {
  const tm_element_info* element = nullptr;
  int count = 0;
  double min_scaled_jacobian = 0;
  double max_scaled_jacobian = 0;
  double max_edge_ratio = 0;
  int inverted = 0;
  double volume = 0;  ///< of the cells that are not inverted
};

/// Quality of a whole mesh.
struct MeshQuality {
  std::vector<CellQuality> cells;         ///< mesh.cell_count(), mesh-wide cell order
  std::vector<ElementTypeQuality> types;  ///< one per block, in block order
  std::vector<int> inverted_cells;        ///< mesh-wide indices, increasing
  double max_edge_ratio = 0;
  double volume = 0;  ///< total of the cells that are not inverted
};

/// Quality of one cell of reference element `element` in a `dim`-D mesh
/// (2 or 3); `xyz` holds element.nodes by 3 coordinates in our node order.
CellQuality cell_quality(const tm_element_info& element, int dim, std::span<const double> xyz);

/// The scaled Jacobian alone (see the file comment).
double scaled_jacobian(const tm_element_info& element, int dim, std::span<const double> xyz);

/// Longest over shortest corner-to-corner edge.
double edge_ratio(const tm_element_info& element, std::span<const double> xyz);

/// Volume (area in 2D) by the default quadrature rule; NaN when det J <= 0
/// at a quadrature point.
double cell_volume(const tm_element_info& element, int dim, std::span<const double> xyz);

/// Quality of every cell of `mesh`, with per-type summaries.
MeshQuality mesh_quality(const Mesh& mesh);

/// The coordinates of cell `local` of `block`: nodes by 3.
std::vector<double> cell_coordinates(const Mesh& mesh, const ElementBlock& block, int local);

}  // namespace tensormass

#endif
