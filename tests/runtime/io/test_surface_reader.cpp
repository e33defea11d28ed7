// read_surface: STL (ASCII with named solids, binary, binary whose header
// starts with "solid"), OBJ (v/vt/vn corners, quads, negative indices,
// groups), Gmsh .msh (2.2 and 4.1) and the committed test surfaces.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "support/test_surfaces.hpp"
#include "tensormass/io/surface_reader.hpp"
#include "tensormass/surface/surface.hpp"

namespace {

using namespace surfacetest;
using tensormass::check_closed_surface;
using tensormass::enclosed_volume;
using tensormass::read_surface;
using test_support::TempDir;

void expect_unit_tetrahedron(TriangleSurface& surface) {
  EXPECT_EQ(surface.point_count(), 4);  // 12 corners merged
  EXPECT_EQ(surface.triangle_count(), 4);
  EXPECT_TRUE(check_closed_surface(surface).empty());
  EXPECT_NEAR(enclosed_volume(surface), 1.0 / 6, 1e-15);
}

TEST(SurfaceReader, AsciiStlTwoNamedSolidsArePatches) {
  TempDir dir;
  const std::string path = dir.write("tet.stl", ascii_stl(unit_tetrahedron()));
  TriangleSurface surface = read_surface(path);
  expect_unit_tetrahedron(surface);
  ASSERT_EQ(surface.patch_names, (std::vector<std::string>{"bottom", "sides"}));
  EXPECT_EQ(surface.patches, (std::vector<int>{0, 0, 1, 1}));
  EXPECT_EQ(surface.source, path);
  EXPECT_EQ(surface.source_ids, (std::vector<long>{1, 2, 3, 4}));
  EXPECT_EQ(surface.describe_triangle(2), "triangle 2 (facet 3 in tet.stl)");
}

TEST(SurfaceReader, AsciiStlToleratesCaseCrlfAndUnnamedSolid) {
  TempDir dir;
  const std::string text =
      "SOLID\r\n"
      "facet normal 0 0 -1\r\nouter loop\r\nvertex 0 0 0\r\nvertex 0 1 0\r\nvertex 1 0 0\r\nendloop\r\nendfacet\r\n"
      "FACET NORMAL 0 0 0\r\nOUTER LOOP\r\nVERTEX 0 0 0\r\nVERTEX 1 0 0\r\nVERTEX 0 0 1\r\nENDLOOP\r\nENDFACET\r\n"
      "facet normal nan nan nan\n outer loop\n vertex 0 0 0\n vertex 0 0 1\n vertex 0 1 0\n endloop\n endfacet\n"
      "facet normal 1 1 1\n outer loop\n vertex 1e0 0 0\n vertex 0 +1 0\n vertex 0 0 1.0\n endloop\n endfacet\n"
      "endsolid\r\n";
  TriangleSurface surface = read_surface(dir.write("TET.STL", text));
  expect_unit_tetrahedron(surface);
  EXPECT_EQ(surface.patch_names, (std::vector<std::string>{""}));
}

TEST(SurfaceReader, BinaryStl) {
  TempDir dir;
  TriangleSurface surface =
      read_surface(dir.write("tet.stl", binary_stl(unit_tetrahedron(), "exported by a CAD tool")));
  expect_unit_tetrahedron(surface);
  EXPECT_EQ(surface.patch_names, (std::vector<std::string>{""}));
}

TEST(SurfaceReader, BinaryStlWhoseHeaderStartsWithSolid) {
  TempDir dir;
  // Text-only header and facet bytes that happen to be printable are still binary: 84 + 50 n == size.
  TriangleSurface surface = read_surface(dir.write("tet.stl", binary_stl(unit_tetrahedron(), "solid tet")));
  expect_unit_tetrahedron(surface);
}

TEST(SurfaceReader, BinaryStlIcosphereRoundTrip) {
  TempDir dir;
  const TriangleSurface ball = make_icosphere(2.0, 3);
  TriangleSurface surface = read_surface(dir.write("ball.stl", binary_stl(ball, "solid ball")));
  EXPECT_EQ(surface.point_count(), ball.point_count());
  EXPECT_EQ(surface.triangle_count(), ball.triangle_count());
  EXPECT_TRUE(check_closed_surface(surface).empty());
  EXPECT_NEAR(enclosed_volume(surface), enclosed_volume(ball), 1e-5 * enclosed_volume(ball));  // float coordinates
}

TEST(SurfaceReader, ObjWithTextureNormalIndicesQuadsAndGroups) {
  TempDir dir;
  // The unit cube: quads with v/vt/vn, v//vn and v/vt corners, negative indices, two groups.
  const std::string text =
      "# cube\nmtllib cube.mtl\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
      "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1 1.0\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\nvn 0 0 -1\n"
      "o cube\ng bottom\nusemtl skin\ns off\n"
      "f 1/1/2 4/2/2 3/3/2 2/1/2\n"
      "g sides\n"
      "f 1//1 2//1 6//1 5//1\n"
      "f 2/1 3/2 7/3 6/1\n"
      "f 3 4 8 7\n"
      "f -8 -4 -1 -5   # 1 5 8 4 written relative to the 8 vertices\n"
      "g top\n"
      "f 5/1/1 6/2/1 7/3/1 8/1/1\n";
  TriangleSurface surface = read_surface(dir.write("cube.obj", text));
  EXPECT_EQ(surface.point_count(), 8);
  ASSERT_EQ(surface.triangle_count(), 12);
  EXPECT_EQ(surface.patch_names, (std::vector<std::string>{"bottom", "sides", "top"}));
  EXPECT_EQ(surface.patches, (std::vector<int>{0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 2, 2}));
  EXPECT_EQ(surface.source_ids[0], 20);  // line of the first face
  EXPECT_EQ(surface.describe_triangle(0), "triangle 0 (face at line 20 in cube.obj)");
  EXPECT_TRUE(check_closed_surface(surface).empty());
  EXPECT_DOUBLE_EQ(enclosed_volume(surface), 1.0);
}

TEST(SurfaceReader, ObjPolygonIsFanTriangulatedAndDuplicatesMerged) {
  TempDir dir;
  // A hexagonal prism: two hexagons and six quads; the top ring is listed twice (points 13..18 repeat 7..12).
  std::string text;
  for (int level = 0; level < 3; ++level)
    for (int k = 0; k < 6; ++k) {
      const double angle = std::numbers::pi / 3 * k;
      text += "v " + format(std::cos(angle)) + " " + format(std::sin(angle)) + " " + (level == 0 ? "0" : "1") + "\n";
    }
  text += "f 6 5 4 3 2 1\nf 13 14 15 16 17 18\n";
  for (int k = 0; k < 6; ++k) {
    const int a = k + 1, b = (k + 1) % 6 + 1;
    text += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(b + 6) + " " +
            std::to_string(a + 6) + "\n";
  }
  TriangleSurface surface = read_surface(dir.write("prism.obj", text));
  EXPECT_EQ(surface.point_count(), 12);
  EXPECT_EQ(surface.triangle_count(), 4 + 4 + 12);
  EXPECT_TRUE(check_closed_surface(surface).empty());
  EXPECT_NEAR(enclosed_volume(surface), 3 * std::sqrt(3.0) / 2, 1e-14);
}

// Tetrahedron of unit_tetrahedron() with a tet volume element and a line element.
const char* const kMsh22 =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
    "$PhysicalNames\n3\n2 1 \"bottom\"\n2 2 \"sides\"\n3 3 \"body\"\n$EndPhysicalNames\n"
    "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
    "$Elements\n6\n"
    "1 1 2 0 1 1 2\n"
    "2 2 2 1 1 1 3 2\n"
    "3 2 2 1 1 1 2 4\n"
    "4 2 2 2 2 1 4 3\n"
    "5 2 2 2 2 2 3 4\n"
    "6 4 2 3 3 1 2 3 4\n"
    "$EndElements\n";

TEST(SurfaceReader, GmshMsh22WithPhysicalNames) {
  TempDir dir;
  TriangleSurface surface = read_surface(dir.write("tet.msh", kMsh22));
  expect_unit_tetrahedron(surface);
  EXPECT_EQ(surface.patch_names, (std::vector<std::string>{"bottom", "sides"}));
  EXPECT_EQ(surface.patches, (std::vector<int>{0, 0, 1, 1}));
  EXPECT_EQ(surface.source_ids, (std::vector<long>{2, 3, 4, 5}));
  EXPECT_EQ(surface.describe_triangle(3), "triangle 3 (element 5 in tet.msh)");
}

TEST(SurfaceReader, GmshMsh41) {
  TempDir dir;
  const std::string text =
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
      "$PhysicalNames\n1\n2 7 \"skin\"\n$EndPhysicalNames\n"
      "$Entities\n0 0 1 0\n1 0 0 0 1 1 1 1 7 0\n$EndEntities\n"
      "$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"
      "$Elements\n1 4 1 4\n2 1 2 4\n1 1 3 2\n2 1 2 4\n3 1 4 3\n4 2 3 4\n$EndElements\n";
  TriangleSurface surface = read_surface(dir.write("tet41.msh", text));
  expect_unit_tetrahedron(surface);
  EXPECT_EQ(surface.patch_names, (std::vector<std::string>{"skin"}));
}

TEST(SurfaceReader, GmshMshWithoutPhysicalGroups) {
  TempDir dir;
  const std::string text =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
      "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
      "$Elements\n4\n1 2 2 0 1 1 3 2\n2 2 2 0 1 1 2 4\n3 2 2 0 1 1 4 3\n4 2 2 0 1 2 3 4\n$EndElements\n";
  TriangleSurface surface = read_surface(dir.write("tet.msh", text));
  expect_unit_tetrahedron(surface);
  EXPECT_EQ(surface.patch_names, (std::vector<std::string>{""}));
}

TEST(SurfaceReader, CommittedSurfaces) {
  const double pi = std::numbers::pi;
  struct Case {
    const char* file;
    double volume;
    std::size_t patches;
  } cases[] = {{"sphere.stl", 4 * pi / 3, 1}, {"torus.stl", 2 * pi * pi * 1.0 * 0.4 * 0.4, 1}};
  for (const Case& c : cases) {
    if (!fs::exists(data_file(c.file))) GTEST_SKIP() << data_file(c.file) << " not present";
    TriangleSurface surface = read_surface(data_file(c.file));
    EXPECT_TRUE(check_closed_surface(surface).empty()) << c.file;
    EXPECT_NEAR(enclosed_volume(surface), c.volume, 0.02 * c.volume) << c.file;
    EXPECT_EQ(surface.patch_names.size(), c.patches) << c.file;
  }
  if (fs::exists(data_file("cut_ball.stl"))) {
    TriangleSurface surface = read_surface(data_file("cut_ball.stl"));
    EXPECT_TRUE(check_closed_surface(surface).empty());
    EXPECT_EQ(surface.patch_names.size(), 2u);
  }
}

}  // namespace
