/// \file mesh_conformity.hpp
/// Conformity of a mesh: every face of every cell (3D) or edge (2D) must be
/// shared, with exactly the same corner nodes, by exactly two cells, or lie
/// on the boundary (one cell). A hanging node shows up as boundary faces
/// (edges) inside the body, a face shared by three cells as an overused face.
/// In 2D "face" below reads "edge".
#ifndef TENSORMASS_MESH_CONFORMITY_HPP
#define TENSORMASS_MESH_CONFORMITY_HPP

#include <vector>

#include "tensormass/mesh/mesh.hpp"

namespace tensormass {

struct ConformityReport {
  int interior_faces = 0;  ///< faces shared by two cells
  int overused_faces = 0;  ///< faces (by corner node set) used by three or more cells
  /// Faces used by one cell: their corner nodes, sorted ascending (3 or 4
  /// each in 3D, the 2 end nodes in 2D).
  std::vector<std::vector<int>> boundary_faces;
};

/// Counts how many cells use each face (3D) or edge (2D), by corner nodes as a set.
ConformityReport check_conformity(const Mesh& mesh);

}  // namespace tensormass

#endif
