// Legacy VTK reader (.vtk): files written by meshio (tests/data/meshes;
// versions 4.2 and 5.1, ASCII and BINARY) read to the same mesh as the Gmsh
// file they came from, and the legacy keywords a reader meets
// (SCALARS/LOOKUP_TABLE, FIELD, POINT_DATA, METADATA) on a file written here.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "support/test_meshes.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace {

using tensormass::Mesh;

class MeshioVtkFile : public testing::TestWithParam<std::string> {};

TEST_P(MeshioVtkFile, ReadsToTheSameMeshAsTheGmshFile) {
  const std::string& file = GetParam();
  meshtest::expect_same_mesh_as_gmsh(file, file.substr(0, file.find('.')));
}

INSTANTIATE_TEST_SUITE_P(Meshio, MeshioVtkFile,
                         testing::Values("box_hex_o2.v51.vtk", "box_tet_o1.v51b.vtk", "hybrid_o1.v42b.vtk",
                                         "plate2d_o2.v42.vtk"),
                         [](const testing::TestParamInfo<std::string>& info) {
                           return meshtest::test_name_of(info.param);
                         });

// Classic legacy layout with SCALARS + LOOKUP_TABLE, POINT_DATA to skip,
// a VTK 9 METADATA block and a "group" array when no gmsh:physical exists.
TEST(LegacyVtkReader, AttributesAreSkippedAndScalarsMakeGroups) {
  test_support::TempDir dir;
  const std::string path = dir.write("legacy.vtk",
                                     "# vtk DataFile Version 3.0\nhand written\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                                     "FIELD FieldData 1\nTIME 1 1 double\n0.5\n"
                                     "POINTS 5 float\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n"
                                     "METADATA\nINFORMATION 0\n\n"
                                     "CELLS 3 11\n4 0 1 2 3\n1 4\n3 0 1 2\n"
                                     "CELL_TYPES 3\n10\n1\n5\n"
                                     "POINT_DATA 5\nVECTORS u double\n0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n"
                                     "CELL_DATA 3\nSCALARS group int 1\nLOOKUP_TABLE default\n4\n9\n4\n"
                                     "SCALARS quality double\nLOOKUP_TABLE default\n1.5\n2.5\n3.5\n");
  // The vertex (point 4) lies on no tetrahedron: its group cannot be built.
  meshtest::expect_input_error(path, {"legacy.vtk:", "cell 1 (point)", "node 4", "belongs to no 3D element"});
  const std::string fixed = dir.write(
      "legacy2.vtk", test_support::read_file(path).replace(test_support::read_file(path).find("1 4\n"), 4, "1 3\n"));
  const Mesh mesh = tensormass::read_mesh(fixed);
  EXPECT_EQ(mesh.cell_count(), 1);
  ASSERT_EQ(mesh.groups.size(), 2u);
  EXPECT_EQ(mesh.groups[0].name, "region_4");
  EXPECT_EQ(mesh.groups[0].cells, (std::vector<int>{0}));
  EXPECT_EQ(mesh.groups[0].facets.count(), 1);
  EXPECT_EQ(mesh.groups[1].name, "region_9");
  EXPECT_EQ(mesh.groups[1].dim, 0);
  EXPECT_EQ(mesh.groups[1].nodes, (std::vector<int>{3}));
}

}  // namespace
