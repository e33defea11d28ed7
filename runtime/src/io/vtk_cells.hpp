/// \file vtk_cells.hpp
/// Internal (not installed): what the legacy (.vtk) and XML (.vtu) VTK
/// readers share. Both read an unstructured grid (points, cell offsets and
/// connectivity, VTK cell types, a group value per cell) into a Grid;
/// build_mesh maps the VTK cell types to our elements (their node order
/// included) and builds the Mesh.
#ifndef TENSORMASS_IO_VTK_CELLS_HPP
#define TENSORMASS_IO_VTK_CELLS_HPP

#include <cstddef>
#include <string_view>
#include <vector>

#include "common/input_cursor.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace tensormass::detail::vtk {

/// An unstructured grid as read, before mapping to our elements.
struct Grid {
  std::vector<double> points;    ///< point count by 3
  std::vector<long> offsets{0};  ///< cells + 1: cell c's nodes are connectivity[offsets[c] .. offsets[c+1])
  std::vector<long> connectivity;
  std::vector<long> types;    ///< VTK cell type per cell
  std::vector<long> regions;  ///< group value per cell; empty when the file has none
  std::vector<Location> cell_where;
  Location points_where;
};

/// Takes the name of a cell data array; returns its rank among the arrays
/// that define groups (0: gmsh:physical, 1: region, 2: group; lower is
/// better), -1 for any other name.
int region_priority(std::string_view name);

/// Takes a grid read from `in` (offsets already checked); returns its Mesh,
/// one group "region_V" per group value V. Throws InputError (through `in`,
/// at the cell's location) for a VTK type we have no element for (the
/// message lists the supported ones) or a cell with the wrong node count.
Mesh build_mesh(const InputCursor& in, const Grid& grid);

/// Takes a grid and the location its cells were read at; checks its offsets
/// (non-decreasing, within and ending at the connectivity size; each
/// reader checks the leading 0 itself) from cell `first_cell` on (the cells
/// before it were checked already). Returns
/// nothing; throws InputError at `where` on the first offset out of order.
void check_offsets(const InputCursor& in, const Grid& grid, Location where, std::size_t first_cell = 0);

/// Takes a value read as a double; returns true when it is finite, whole and
/// below 9e15 in magnitude (so exact as a long).
bool is_integer_value(double value);

/// Takes values read as doubles; returns them as longs. Throws InputError at
/// `where`, naming the array `what` and the value's index, for the first one
/// that is not an integer (is_integer_value).
std::vector<long> to_integers(const InputCursor& in, const std::vector<double>& values, Location where,
                              std::string_view what);

}  // namespace tensormass::detail::vtk

#endif
