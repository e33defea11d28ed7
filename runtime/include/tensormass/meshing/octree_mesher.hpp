/// \file octree_mesher.hpp
/// Hex-dominant mixed volume meshes of a closed triangle surface.
///
/// Stages (each timed in OctreeMeshReport::stage_seconds):
///   1. refine    an octree over the surface's box, refined near the surface
///                (`surface_levels` levels below `size`) and in regions of
///                interest; cells entirely outside are dropped
///   2. balance   strong 2:1 balance (face, edge and corner neighbours)
///   3. classify  a leaf joins the core when its corners, face centres and
///                centre lie inside, at least `margin` of its edge from the surface
///   4. clean     core cells are removed until every core face meets either
///                core cells on its whole area or none, the core's boundary
///                is a 2-manifold and the core is one face-connected piece
///   5. cut       each core cell becomes one hexahedron when its faces carry
///                no extra node, else a transition: a centre node with a
///                pyramid on each quadrilateral and a tetrahedron on each
///                triangle of its faces (faces with hanging nodes are fanned
///                from their centre); each exposed square face gets an
///                outward pyramid cap so that the core's boundary is all triangles
///   6. layer     a layer of prisms on the surface's triangles, their tops
///                the surface offset inward along angle-weighted point normals
///                (checked: no self-intersection, no flat prism, the core
///                inside; thinner or left out otherwise)
///   7. gap       Gmsh's Delaunay mesher fills the layer between the core's
///                boundary and the input surface with tetrahedra, keeping
///                both triangulations, so the mesh's boundary IS the input surface
///   8. groups    body (all cells), surface (the input triangles), one facet
///                group per named surface patch, one cell group per region
#ifndef TENSORMASS_OCTREE_MESHER_HPP
#define TENSORMASS_OCTREE_MESHER_HPP

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "tensormass/mesh/mesh.hpp"
#include "tensormass/surface/surface.hpp"

namespace tensormass {

/// A sphere where cells are refined to edge `size` or less.
struct RegionOfInterest {
  std::array<double, 3> centre{};
  double radius = 0;
  double size = 0;
};

/// A named closed surface: cells whose centroid lies inside join group `name`.
struct VolumeRegion {
  std::string name;
  TriangleSurface surface;
};

struct OctreeMeshOptions {
  double size = 0;         ///< edge of the interior hexahedra (> 0)
  int surface_levels = 1;  ///< levels of refinement (halvings of `size`) near the surface, 0..8
  std::vector<RegionOfInterest> regions_of_interest;
  std::vector<VolumeRegion> regions;  ///< first match wins
  double margin = 0.35;               ///< core cells stay this fraction of their edge inside the surface
  double cap_height = 0.25;           ///< height of the caps on exposed core faces, in cell edges
  /// Thickness of the layer of prisms on the surface's triangles, in edges
  /// of the cells near the surface (size / 2^surface_levels); 0: no layer.
  double boundary_layer = 0.25;
  /// Called with a stage name as each stage starts (progress).
  std::function<void(const std::string&)> on_stage;
};

struct OctreeMeshReport {
  int leaves = 0;                  ///< octree leaves after balance
  int core_cells = 0;              ///< leaves kept in the core
  int removed_for_conformity = 0;  ///< core cells removed by the clean stage
  int core_hexahedra = 0, transition_cells = 0, caps = 0, gap_tetrahedra = 0;
  int boundary_prisms = 0;              ///< 0 when the layer was left out (see warnings)
  double boundary_layer_thickness = 0;  ///< as built (halved from the option's when needed)
  double surface_volume = 0;            ///< enclosed by the input surface
  double mesh_volume = 0;               ///< sum of the cells' volumes
  std::vector<std::pair<std::string, double>> stage_seconds;
  std::vector<std::string> warnings;
};

/// Meshes the volume bounded by `surface` (closed, outward; see
/// check_closed_surface). Throws InputError for bad options and
/// NumericalError when Gmsh cannot fill the gap.
Mesh mesh_surface_volume(const TriangleSurface& surface, const OctreeMeshOptions& options,
                         OctreeMeshReport* report = nullptr);

}  // namespace tensormass

#endif
