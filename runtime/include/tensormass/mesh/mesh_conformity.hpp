/// \file mesh_conformity.hpp
/// Conformity of a 3D mesh: every face of every cell must be shared, with
/// exactly the same corner nodes, by exactly two cells, or lie on the
/// boundary (one cell). A hanging node shows up as boundary faces inside the
/// body, a face shared by three cells as an overused face.
#ifndef TENSORMASS_MESH_CONFORMITY_HPP
#define TENSORMASS_MESH_CONFORMITY_HPP

#include <vector>

#include "tensormass/mesh/mesh.hpp"

namespace tensormass {

struct ConformityReport {
  int interior_faces = 0;  ///< faces shared by two cells
  int overused_faces = 0;  ///< faces (by corner node set) used by three or more cells
  /// Faces used by one cell: their corner nodes, sorted ascending (3 or 4 each).
  std::vector<std::vector<int>> boundary_faces;
};

/// Counts how many cells use each face (corner nodes as a set).
ConformityReport check_conformity(const Mesh& mesh);

}  // namespace tensormass

#endif
