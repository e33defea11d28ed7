/// \file gap_mesher.hpp
/// Internal to the octree mesher (not installed): fills the region between
/// closed triangle surfaces with tetrahedra through Gmsh's 3D Delaunay
/// mesher, keeping the given surface triangulations unchanged.
#ifndef TENSORMASS_GAP_MESHER_HPP
#define TENSORMASS_GAP_MESHER_HPP

#include <array>
#include <vector>

namespace tensormass::detail {

struct GapMesh {
  std::vector<double> new_positions;     ///< #N by 3: nodes Gmsh added inside the gap
  std::vector<std::array<int, 4>> tets;  ///< node indices: < positions' count, or count + k for new node k
};

/// Tetrahedralises the volume bounded by `outer` (outward triangles) and
/// `inner` (the core's boundary, triangles oriented away from the core;
/// may be empty). Triangles index `positions` (#P by 3); the two surfaces
/// share no node. Throws NumericalError when Gmsh fails or changes a surface.
GapMesh fill_gap(const std::vector<double>& positions, const std::vector<std::array<int, 3>>& outer,
                 const std::vector<std::array<int, 3>>& inner, int threads);

}  // namespace tensormass::detail

#endif
