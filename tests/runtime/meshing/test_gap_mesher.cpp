// Filling the gap between closed surfaces with Gmsh's tetrahedra
// (meshing/gap_mesher.hpp): the tets fill the volume between the outer
// surface and the core, keep both triangulations as their boundary faces,
// index the given positions (unused ones included) before the new nodes,
// and a surface Gmsh cannot fill is a NumericalError.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "meshing/gap_mesher.hpp"
#include "support/test_surfaces.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::detail {
namespace {

using Triangles = std::vector<std::array<int, 3>>;

/// Appends the box [lo, hi] (n by n squares a face, outward) to `positions`; its triangles.
Triangles add_box(std::vector<double>& positions, const surfacetest::Vec& lo, const surfacetest::Vec& hi, int n) {
  const TriangleSurface box = surfacetest::make_box(lo, hi, n);
  const int offset = static_cast<int>(positions.size() / 3);
  positions.insert(positions.end(), box.points.begin(), box.points.end());
  Triangles triangles;
  for (int t = 0; t < box.triangle_count(); ++t)
    triangles.push_back(
        {offset + box.triangles[3 * t], offset + box.triangles[3 * t + 1], offset + box.triangles[3 * t + 2]});
  return triangles;
}

/// The position of node `n` of the gap mesh (given, or added by Gmsh).
surfacetest::Vec node(const std::vector<double>& positions, const GapMesh& gap, int n) {
  const int known = static_cast<int>(positions.size() / 3);
  const double* x = n < known ? &positions[3 * n] : &gap.new_positions[3 * (n - known)];
  return {x[0], x[1], x[2]};
}

double tet_volume(const surfacetest::Vec& a, const surfacetest::Vec& b, const surfacetest::Vec& c,
                  const surfacetest::Vec& d) {
  using surfacetest::cross, surfacetest::dot, surfacetest::minus;
  return dot(minus(b, a), cross(minus(c, a), minus(d, a))) / 6;
}

/// Expects the tets' faces used once to be exactly the given triangles, and
/// no face to be used more than twice.
void expect_boundary_is(const GapMesh& gap, const std::vector<Triangles>& surfaces) {
  std::map<std::array<int, 3>, int> uses;
  for (const auto& tet : gap.tets)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> face{};
      for (int c = 0, k = 0; c < 4; ++c)
        if (c != skip) face[k++] = tet[c];
      std::sort(face.begin(), face.end());
      ++uses[face];
    }
  std::set<std::array<int, 3>> boundary, expected;
  for (const auto& [face, count] : uses) {
    EXPECT_LE(count, 2);
    if (count == 1) boundary.insert(face);
  }
  for (const Triangles& surface : surfaces)
    for (std::array<int, 3> triangle : surface) {
      std::sort(triangle.begin(), triangle.end());
      expected.insert(triangle);
    }
  EXPECT_EQ(boundary, expected);
}

TEST(GapMesher, FillsAClosedSurfaceKeepingItsTriangles) {
  std::vector<double> positions;
  const Triangles outer = add_box(positions, {0, 0, 0}, {2, 1, 1}, 2);
  const GapMesh gap = fill_gap(positions, outer, {}, 1);
  ASSERT_FALSE(gap.tets.empty());
  double volume = 0;
  for (const auto& tet : gap.tets) {
    const double v = std::abs(tet_volume(node(positions, gap, tet[0]), node(positions, gap, tet[1]),
                                         node(positions, gap, tet[2]), node(positions, gap, tet[3])));
    EXPECT_GT(v, 0);
    volume += v;
  }
  EXPECT_NEAR(volume, 2.0, 1e-12);
  expect_boundary_is(gap, {outer});
  EXPECT_EQ(gap.new_positions.size() % 3, 0u);
}

TEST(GapMesher, FillsOnlyTheShellAroundTheCore) {
  std::vector<double> positions;
  const Triangles outer = add_box(positions, {0, 0, 0}, {3, 3, 3}, 3);
  const Triangles inner = add_box(positions, {1, 1, 1}, {2, 2, 2}, 1);  // outward of the core: into the gap
  const GapMesh gap = fill_gap(positions, outer, inner, 1);
  double volume = 0;
  for (const auto& tet : gap.tets) {
    surfacetest::Vec centroid{0, 0, 0};
    for (int c = 0; c < 4; ++c)
      for (int a = 0; a < 3; ++a) centroid[a] += node(positions, gap, tet[c])[a] / 4;
    const bool in_core = std::all_of(centroid.begin(), centroid.end(), [](double x) { return x > 1 && x < 2; });
    EXPECT_FALSE(in_core) << "a tet in the core";
    volume += std::abs(tet_volume(node(positions, gap, tet[0]), node(positions, gap, tet[1]),
                                  node(positions, gap, tet[2]), node(positions, gap, tet[3])));
  }
  EXPECT_NEAR(volume, 26.0, 1e-11);
  expect_boundary_is(gap, {outer, inner});
}

TEST(GapMesher, TetsIndexTheGivenPositionsThenTheNewNodes) {
  // Nodes 0..4 are used by no surface: the tets still index positions as given.
  std::vector<double> positions(15, 7.0);
  const Triangles outer = add_box(positions, {0, 0, 0}, {1, 1, 1}, 3);
  const GapMesh gap = fill_gap(positions, outer, {}, 1);
  const int known = static_cast<int>(positions.size() / 3);
  const int total = known + static_cast<int>(gap.new_positions.size() / 3);
  std::set<int> used;
  for (const auto& tet : gap.tets)
    for (int n : tet) {
      EXPECT_GE(n, 5);
      EXPECT_LT(n, total);
      used.insert(n);
    }
  for (int n = known; n < total; ++n) EXPECT_EQ(used.count(n), 1u) << "new node " << n << " in no tet";
  // New nodes lie strictly inside the box.
  for (std::size_t k = 0; k < gap.new_positions.size(); ++k) {
    EXPECT_GT(gap.new_positions[k], 0);
    EXPECT_LT(gap.new_positions[k], 1);
  }
  expect_boundary_is(gap, {outer});
}

TEST(GapMesher, ASurfaceGmshCannotFillIsANumericalError) {
  std::vector<double> positions;
  Triangles outer = add_box(positions, {0, 0, 0}, {1, 1, 1}, 1);
  outer.pop_back();  // an open box
  try {
    fill_gap(positions, outer, {}, 1);
    ADD_FAILURE() << "an open box was filled";
  } catch (const NumericalError& error) {
    EXPECT_EQ(std::string(error.what()).rfind("Gmsh could not fill the gap between the octree core and the surface", 0),
              0u)
        << error.what();
  }
}

}  // namespace
}  // namespace tensormass::detail
