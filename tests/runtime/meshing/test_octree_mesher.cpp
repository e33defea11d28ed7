// The octree mesher on closed test surfaces: conformity, positivity, volume,
// groups, refinement, and the 50k-element size in under a minute.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <set>
#include <string>

#include "tensormass/common/errors.hpp"
#include "tensormass/io/surface_reader.hpp"
#include "tensormass/mesh/mesh_conformity.hpp"
#include "tensormass/mesh/mesh_quality.hpp"
#include "tensormass/meshing/octree_mesher.hpp"
#include "tensormass/surface/surface.hpp"

namespace tensormass {
namespace {

std::string surface_path(const std::string& name) {
  return std::string(TENSORMASS_SOURCE_DIR) + "/tests/data/surfaces/" + name + ".stl";
}

TriangleSurface load(const std::string& name) {
  TriangleSurface surface = read_surface(surface_path(name));
  check_closed_surface(surface);
  return surface;
}

/// The input triangles as sorted node triples of the mesh (surface points
/// are appended to the mesh's nodes in their order).
std::set<std::vector<int>> surface_faces(const Mesh& mesh) {
  std::set<std::vector<int>> faces;
  const FacetSet& facets = mesh.group("surface")->facets;
  for (int f = 0; f < facets.count(); ++f) {
    std::vector<int> face(facets.nodes.begin() + facets.offsets[f], facets.nodes.begin() + facets.offsets[f + 1]);
    std::sort(face.begin(), face.end());
    faces.insert(face);
  }
  return faces;
}

int count_of(const Mesh& mesh, const std::string& type) {
  for (const ElementBlock& block : mesh.blocks)
    if (block.element->name == type) return block.count();
  return 0;
}

struct Shape {
  std::string name;
  double exact_volume;  ///< of the smooth shape the STL approximates
  double size;
};

class MesherShapes : public ::testing::TestWithParam<Shape> {};

TEST_P(MesherShapes, ConformingPositiveAndFillsTheSurface) {
  const Shape& shape = GetParam();
  const TriangleSurface surface = load(shape.name);
  OctreeMeshOptions options;
  options.size = shape.size;
  OctreeMeshReport report;
  const Mesh mesh = mesh_surface_volume(surface, options, &report);

  // Positivity: no inverted cell, every type's minimum scaled Jacobian > 0.
  const MeshQuality quality = mesh_quality(mesh);
  EXPECT_TRUE(quality.inverted_cells.empty());
  for (const ElementTypeQuality& type : quality.types) EXPECT_GT(type.min_scaled_jacobian, 0.02) << type.element->name;

  // Conformity: no face used thrice, and the only unshared faces are exactly
  // the input triangles (a hanging node would leave unshared faces inside).
  const ConformityReport conformity = check_conformity(mesh);
  EXPECT_EQ(conformity.overused_faces, 0);
  const std::set<std::vector<int>> boundary(conformity.boundary_faces.begin(), conformity.boundary_faces.end());
  EXPECT_EQ(boundary, surface_faces(mesh));
  EXPECT_EQ(static_cast<int>(boundary.size()), surface.triangle_count());

  // Volume: equal to the enclosed volume (no gap, no overlap), within 2 % of the smooth shape's.
  EXPECT_NEAR(quality.volume, enclosed_volume(surface), 1e-9 * enclosed_volume(surface));
  EXPECT_NEAR(quality.volume, shape.exact_volume, 0.02 * shape.exact_volume);

  // Hex-dominant inside: hexahedra, transition pyramids and tetrahedra are all there.
  EXPECT_GT(count_of(mesh, "hex8"), 0);
  EXPECT_GT(count_of(mesh, "pyramid5"), 0);
  EXPECT_GT(count_of(mesh, "tet4"), 0);
  // The boundary layer: one prism on each surface triangle.
  EXPECT_EQ(count_of(mesh, "prism6"), surface.triangle_count());
  EXPECT_EQ(report.boundary_prisms, surface.triangle_count());
  EXPECT_TRUE(report.warnings.empty());
  double hex_volume = 0;
  for (const ElementTypeQuality& type : quality.types)
    if (std::string(type.element->name) == "hex8") hex_volume = type.volume;
  EXPECT_GT(hex_volume, 0.3 * quality.volume);

  // Groups.
  ASSERT_NE(mesh.group("body"), nullptr);
  EXPECT_EQ(static_cast<int>(mesh.group("body")->cells.size()), mesh.cell_count());
  ASSERT_NE(mesh.group("surface"), nullptr);
  EXPECT_EQ(report.core_cells, report.core_hexahedra + report.transition_cells);
}

INSTANTIATE_TEST_SUITE_P(
    Shapes, MesherShapes,
    ::testing::Values(Shape{"sphere", 4.0 / 3.0 * std::numbers::pi, 0.25},
                      Shape{"torus", 2 * std::numbers::pi* std::numbers::pi * 1.0 * 0.16, 0.2},
                      // Ball of radius 1 cut at z = 0.4: minus a cap of height 0.6.
                      Shape{"cut_ball", 4.0 / 3.0 * std::numbers::pi - std::numbers::pi * 0.36 * 2.4 / 3.0, 0.25}),
    [](const auto& info) { return info.param.name; });

TEST(OctreeMesher, PatchesBecomeFacetGroups) {
  const TriangleSurface surface = load("cut_ball");
  OctreeMeshOptions options;
  options.size = 0.3;
  const Mesh mesh = mesh_surface_volume(surface, options);
  ASSERT_NE(mesh.group("flat"), nullptr);
  ASSERT_NE(mesh.group("round"), nullptr);
  EXPECT_EQ(mesh.group("flat")->facets.count() + mesh.group("round")->facets.count(), surface.triangle_count());
  // Every node of the flat patch lies on the plane z = 0.4.
  for (int node : mesh.group("flat")->nodes) EXPECT_NEAR(mesh.rest_positions[3 * node + 2], 0.4, 1e-9);
}

/// Smallest hexahedron edge among hexes whose centre lies within `radius` of `centre`.
double smallest_hex_edge_near(const Mesh& mesh, std::array<double, 3> centre, double radius, bool inside) {
  double smallest = INFINITY;
  for (const ElementBlock& block : mesh.blocks) {
    if (std::string(block.element->name) != "hex8") continue;
    for (int local = 0; local < block.count(); ++local) {
      const auto nodes = block.cell_nodes(local);
      double c[3] = {0, 0, 0};
      for (int n : nodes)
        for (int a = 0; a < 3; ++a) c[a] += mesh.rest_positions[3 * n + a] / 8;
      const double d = std::hypot(c[0] - centre[0], c[1] - centre[1], c[2] - centre[2]);
      if ((d <= radius) != inside) continue;
      smallest = std::min(smallest, std::abs(mesh.rest_positions[3 * nodes[1]] - mesh.rest_positions[3 * nodes[0]]));
    }
  }
  return smallest;
}

TEST(OctreeMesher, RegionOfInterestIsRefined) {
  const TriangleSurface surface = load("sphere");
  OctreeMeshOptions options;
  options.size = 0.4;
  options.surface_levels = 1;
  const Mesh plain = mesh_surface_volume(surface, options);
  options.regions_of_interest.push_back({{0.1, 0.0, 0.0}, 0.3, 0.05});
  OctreeMeshReport report;
  const Mesh refined = mesh_surface_volume(surface, options, &report);
  EXPECT_GT(refined.cell_count(), plain.cell_count());
  EXPECT_NEAR(smallest_hex_edge_near(refined, {0.1, 0, 0}, 0.3, true), 0.05, 1e-12);
  EXPECT_GE(smallest_hex_edge_near(plain, {0.1, 0, 0}, 0.3, true), 0.2 - 1e-12);
  EXPECT_TRUE(check_conformity(refined).overused_faces == 0);
  EXPECT_TRUE(mesh_quality(refined).inverted_cells.empty());
}

TEST(OctreeMesher, SurfaceLevelsRefineNearTheSurfaceOnly) {
  const TriangleSurface surface = load("sphere");
  OctreeMeshOptions options;
  options.size = 0.4;
  options.surface_levels = 2;
  const Mesh mesh = mesh_surface_volume(surface, options);
  // Near the surface: size / 4; deeper: coarser hexahedra (size / 2 by the
  // 2:1 balance on this small ball).
  EXPECT_NEAR(smallest_hex_edge_near(mesh, {0, 0, 0}, 0.75, false), 0.1, 1e-12);
  EXPECT_NEAR(smallest_hex_edge_near(mesh, {0, 0, 0}, 0.5, true), 0.2, 1e-12);
}

TEST(OctreeMesher, RegionsGroupCellsByCentroid) {
  const TriangleSurface surface = load("sphere");
  TriangleSurface inner = surface;
  for (double& x : inner.points) x *= 0.5;
  inner.source = "half sphere";
  OctreeMeshOptions options;
  options.size = 0.25;
  options.regions.push_back({"core", inner});
  const Mesh mesh = mesh_surface_volume(surface, options);
  const Group* core = mesh.group("core");
  ASSERT_NE(core, nullptr);
  EXPECT_GT(core->cells.size(), 0u);
  EXPECT_LT(core->cells.size(), static_cast<std::size_t>(mesh.cell_count()));
  const SurfaceDistance distance(inner);
  for (int cell : core->cells) {
    const auto [b, local] = mesh.locate(cell);
    const auto nodes = mesh.blocks[b].cell_nodes(local);
    double c[3] = {0, 0, 0};
    for (int n : nodes)
      for (int a = 0; a < 3; ++a) c[a] += mesh.rest_positions[3 * n + a] / nodes.size();
    EXPECT_TRUE(distance.inside(c));
  }
}

TEST(OctreeMesher, FiftyThousandElementsInUnderAMinute) {
  const TriangleSurface surface = load("torus");
  OctreeMeshOptions options;
  options.size = 0.15;
  options.regions_of_interest.push_back({{1.0, 0.0, 0.0}, 0.35, 0.04});
  const auto start = std::chrono::steady_clock::now();
  const Mesh mesh = mesh_surface_volume(surface, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(mesh.cell_count(), 50000);
  EXPECT_LT(seconds, 60.0);
  RecordProperty("cells", mesh.cell_count());
  RecordProperty("seconds", std::to_string(seconds));
  EXPECT_TRUE(mesh_quality(mesh).inverted_cells.empty());
  EXPECT_EQ(check_conformity(mesh).overused_faces, 0);
}

TEST(OctreeMesher, BadOptionsAreInputErrors) {
  const TriangleSurface surface = load("sphere");
  OctreeMeshOptions options;
  options.size = 0;
  EXPECT_THROW(mesh_surface_volume(surface, options), InputError);
  options.size = 0.2;
  options.surface_levels = 9;
  EXPECT_THROW(mesh_surface_volume(surface, options), InputError);
  options.surface_levels = 1;
  options.regions_of_interest.push_back({{0, 0, 0}, -1, 0.1});
  EXPECT_THROW(mesh_surface_volume(surface, options), InputError);
  options.regions_of_interest.clear();
  options.size = 1e-6;  // far too many cells
  EXPECT_THROW(mesh_surface_volume(surface, options), InputError);
}

TEST(OctreeMesher, NoLayerWhenAskedNone) {
  const TriangleSurface surface = load("cut_ball");
  OctreeMeshOptions options;
  options.size = 0.3;
  options.boundary_layer = 0;
  OctreeMeshReport report;
  const Mesh mesh = mesh_surface_volume(surface, options, &report);
  EXPECT_EQ(count_of(mesh, "prism6"), 0);
  EXPECT_EQ(report.boundary_prisms, 0);
  EXPECT_EQ(check_conformity(mesh).boundary_faces.size(), static_cast<std::size_t>(surface.triangle_count()));
}

TEST(OctreeMesher, SharpSurfaceGoesWithoutALayerAndSaysWhy) {
  // A flat tetrahedron: the normals at its corners lie far more than
  // 60 degrees from the faces around them, so no prism fits there.
  TriangleSurface surface;
  surface.source = "wedge";
  surface.points = {0, 0, 0, 4, 0, 0, 0, 4, 0, 2, 2, 0.3};
  surface.triangles = {0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3};
  surface.patches = {0, 0, 0, 0};
  surface.patch_names = {""};
  OctreeMeshOptions options;
  options.size = 1;
  OctreeMeshReport report;
  const Mesh mesh = mesh_surface_volume(surface, options, &report);
  EXPECT_EQ(report.boundary_prisms, 0);
  ASSERT_FALSE(report.warnings.empty());
  bool said = false;
  for (const std::string& warning : report.warnings)
    said = said || warning.find("no boundary layer") != std::string::npos;
  EXPECT_TRUE(said);
  EXPECT_TRUE(mesh_quality(mesh).inverted_cells.empty());
}

TEST(OctreeMesher, CoarseSizeGivesAnAllTetMeshWithAWarning) {
  const TriangleSurface surface = load("sphere");
  OctreeMeshOptions options;
  options.size = 3.0;
  options.surface_levels = 0;
  OctreeMeshReport report;
  const Mesh mesh = mesh_surface_volume(surface, options, &report);
  EXPECT_EQ(count_of(mesh, "hex8"), 0);
  EXPECT_EQ(count_of(mesh, "tet4") + count_of(mesh, "prism6"), mesh.cell_count());
  EXPECT_FALSE(report.warnings.empty());
  EXPECT_NEAR(mesh_quality(mesh).volume, enclosed_volume(surface), 1e-9);
}

}  // namespace
}  // namespace tensormass
