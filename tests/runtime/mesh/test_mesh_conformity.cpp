// check_conformity in 2D: edges shared by two cells, boundary edges, a
// hanging node, an edge used three times.
#include <gtest/gtest.h>

#include <vector>

#include "tensormass/kernels/registry.hpp"
#include "tensormass/mesh/mesh_conformity.hpp"
#include "tensormass/meshing/beam.hpp"

namespace {

using tensormass::Mesh;

/// A 2D mesh of quad4 cells on the given nodes (x, y pairs).
Mesh quads(const std::vector<double>& xy, const std::vector<int>& connectivity) {
  Mesh mesh;
  mesh.dim = 2;
  for (std::size_t k = 0; k < xy.size(); k += 2)
    mesh.rest_positions.insert(mesh.rest_positions.end(), {xy[k], xy[k + 1], 0.0});
  mesh.blocks.push_back({tensormass::Registry::instance().element("quad4"), connectivity, {}, 0});
  return mesh;
}

TEST(MeshConformity2D, BeamEdgesAreInteriorOrBoundary) {
  tensormass::BeamSpec spec;
  spec.cells = {4, 2, 1};
  spec.phases = {{"tri3", 0.5}, {"quad4", 0.5}};
  const tensormass::ConformityReport report = tensormass::check_conformity(tensormass::make_beam(spec));
  // 2 quad columns + 2 tri columns (one diagonal per square): edges of the 4 x 2 grid plus 4 diagonals.
  EXPECT_EQ(report.boundary_faces.size(), 12u);
  EXPECT_EQ(report.interior_faces, (3 * 2 + 4 * 1) + 4);
  EXPECT_EQ(report.overused_faces, 0);
  for (const auto& edge : report.boundary_faces) EXPECT_EQ(edge.size(), 2u);
}

TEST(MeshConformity2D, HangingNodeShowsAsBoundaryEdgesInside) {
  // One 2 x 2 quad on the left, two 1 x 1 quads on the right: node 6 (2, 1) hangs.
  const Mesh mesh = quads({0, 0, 2, 0, 2, 2, 0, 2, 3, 0, 3, 1, 2, 1, 3, 2}, {0, 1, 2, 3, 1, 4, 5, 6, 6, 5, 7, 2});
  const tensormass::ConformityReport report = tensormass::check_conformity(mesh);
  EXPECT_EQ(report.interior_faces, 1);           // 6-5 between the right quads
  EXPECT_EQ(report.boundary_faces.size(), 10u);  // 7 outer + the left quad's 1-2 and the halves 1-6, 6-2
  EXPECT_EQ(report.overused_faces, 0);
}

TEST(MeshConformity2D, EdgeOfThreeCellsIsOverused) {
  const Mesh mesh = quads({0, 0, 1, 0, 1, 1, 0, 1, 2, 0, 2, 1, 1, 2, 0, 2},
                          {0, 1, 2, 3, 1, 4, 5, 2, 1, 2, 6, 7});  // the third quad folds over edge 1-2
  EXPECT_EQ(tensormass::check_conformity(mesh).overused_faces, 1);
}

}  // namespace
