/// \file beam.hpp
/// Test beams of the origin report: a box [0,L]x[0,H] (2D, z = 0) or
/// [0,L]x[0,H]x[0,W] (3D) cut into nx by ny (by nz) squares or cubes, each
/// cut into cells of a chosen "cut" type, possibly several phases along x.
///
/// Cuts (what one square or cube becomes):
///   2D  quad4     1 quad4 (quad8 at order 2)
///       tri3      2 tri3 (tri6); the diagonal joins the corners whose grid
///                 indices I+J are even (alternating "union jack" pattern)
///   3D  hex8      1 hex8 (hex20)
///       tet5      5 tet4 (tet10): one central tet on the corners whose grid
///                 indices I+J+K are even, and 4 corner tets (alternating parity)
///       tet6      6 tet4 (tet10) around the cube's main diagonal (Kuhn)
///       prism6    2 prism6, axis along z, cut by the xy diagonal (0,0)-(1,1)
///       pyramid5  6 pyramid5 on the faces, apex at a new centre node
///
/// Conformity (3D): every square face between two cubes is either kept as a
/// quadrilateral or split by one diagonal that both cubes use. Each cut has a
/// native face pattern (hex8, pyramid5: quads; tet6: low-high diagonal;
/// tet5: even-parity diagonal; prism6: quads on the sides, low-high diagonal
/// on top and bottom). Where two cubes disagree (only at phase interfaces),
/// a quad wins over a diagonal and the low-x cube's diagonal wins over the
/// high-x cube's; a cube whose faces are not its native pattern becomes a
/// transition cube: a centre node with a pyramid5 on each quad face and two
/// tet4 on each split face.
///
/// Order 2 replaces every cell by the registry's quadratic element with its
/// corners (BeamSpec::quadratic chooses among several, else the one with the
/// fewest nodes): mid-edge nodes at edge midpoints, face nodes at face
/// centres, interior nodes at the cell's centre; a cell type with no
/// quadratic version in the registry is refused, naming it.
///
/// Groups of the mesh, in this order:
///   clamp          facets (dim-1) and nodes at x = 0
///   tip            facets and nodes at x = L
///   body           every cell
///   phase_<CUT>    the cells of one phase (e.g. phase_tri3), only when the
///                  beam has two phases or more; transition cells belong to
///                  the phase of their cube
#ifndef TENSORMASS_BEAM_HPP
#define TENSORMASS_BEAM_HPP

#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tensormass/mesh/mesh.hpp"

namespace tensormass {

/// A run of consecutive columns (along x) cut the same way.
struct BeamPhase {
  /// tri3, quad4 (2D); hex8, tet5, tet6, prism6, pyramid5 (3D); or a
  /// quadratic registry element with the corners of one of them (quad8,
  /// quad9, hex20, hex27, prism15, pyramid13, ...): that cut at order 2,
  /// making this element.
  std::string cut;
  double fraction = 1.0;  ///< share of the nx columns, in (0, 1]; fractions sum to 1
};

struct BeamSpec {
  int dim = 2;                                    ///< 2 or 3
  std::array<int, 3> cells{60, 10, 10};           ///< nx, ny, nz (nz unused in 2D)
  std::array<double, 3> size{6.0, 1.0, 1.0};      ///< L, H, W (W unused in 2D)
  std::vector<BeamPhase> phases{{"quad4", 1.0}};  ///< from x = 0 to x = L (set it for 3D, e.g. {{"hex8", 1}})
  int order = 1;                                  ///< 1 linear, 2 quadratic
  /// At order 2, the quadratic elements to make where the registry has
  /// several with one linear element's corners (quad9 rather than quad8,
  /// hex27 rather than hex20); the others get the one with the fewest nodes.
  std::vector<std::string> quadratic;
};

/// The cut names valid in dimension `dim` (2 or 3).
std::span<const std::string_view> beam_cuts(int dim);

/// Parses "CUT:FRACTION,CUT:FRACTION,..." (e.g. "tri3:0.3,quad4:0.7").
/// Throws InputError on malformed text; the values are checked by make_beam.
std::vector<BeamPhase> parse_beam_mix(std::string_view text);

/// Column ranges of the phases: phase p covers columns [bounds[p], bounds[p+1]).
/// Throws InputError when a phase would get no column.
std::vector<int> beam_phase_bounds(const BeamSpec& spec);

/// Throws InputError with a clear message when the spec is not a valid beam
/// (dimension, counts, sizes, unknown or misplaced cut, fractions, order).
void check_beam_spec(const BeamSpec& spec);

/// Builds the conforming beam mesh described by `spec` (see the file comment),
/// every cell with a positive Jacobian. Throws InputError for a bad spec.
Mesh make_beam(const BeamSpec& spec);

}  // namespace tensormass

#endif
