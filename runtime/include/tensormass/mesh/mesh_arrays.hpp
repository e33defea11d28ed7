/// \file mesh_arrays.hpp
/// A Mesh built from plain arrays (Python's Simulation.from_arrays, meshes
/// made in code): points, cells per element type, and named groups of
/// points or cells. Same rules as the file readers (mesh_builder): the
/// highest-dimensional cells are simulated, lower ones only serve groups
/// (facets for pressure loads).
#ifndef TENSORMASS_MESH_ARRAYS_HPP
#define TENSORMASS_MESH_ARRAYS_HPP

#include <string>
#include <utility>
#include <vector>

#include "tensormass/mesh/mesh.hpp"

namespace tensormass {

/// Cells of one element type: `nodes` holds count x (nodes per element)
/// point indices in VTK node order.
struct CellArray {
  std::string element;  ///< a registry name (tet4, hex8, ...) or meshio's (tetra, hexahedron, ...)
  std::vector<long> nodes;
};

struct MeshArrays {
  std::vector<double> points;  ///< point_count x 3 (z = 0 for a 2D mesh)
  std::vector<CellArray> cells;
  /// Named groups of point indices (fixed or prescribed regions, tracks).
  std::vector<std::pair<std::string, std::vector<long>>> point_groups;
  /// Named groups of cell indices, numbered through `cells` in order
  /// (material regions; lower-dimensional cells: pressure facets).
  std::vector<std::pair<std::string, std::vector<long>>> cell_groups;
};

/// Builds and validates the mesh; `source` names it in messages. Throws
/// InputError naming the array and index: an unknown element, a cell row of
/// the wrong length, an index out of range, a non-finite coordinate, a
/// point used by no cell of the mesh's dimension nor any group (its
/// numbering would no longer match `points`).
Mesh mesh_from_arrays(const MeshArrays& arrays, const std::string& source);

}  // namespace tensormass

#endif
