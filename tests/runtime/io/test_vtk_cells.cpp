// What the .vtk and .vtu readers share (io/vtk_cells.hpp), on grids built in
// memory: VTK cell types mapped to our elements and groups, unsupported
// types and wrong node counts named by cell and line, offsets checked from a
// given cell on, and arrays read as doubles taken as exact integers.
// (The same errors reached through whole files: test_read_mesh_errors.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "io/vtk_cells.hpp"
#include "support/input_error.hpp"
#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::detail::vtk {
namespace {

using test_support::input_error;

/// Appends a cell of VTK type `type` on `nodes`, read at line `line`.
void add_cell(Grid& grid, long type, const std::vector<long>& nodes, long line) {
  grid.connectivity.insert(grid.connectivity.end(), nodes.begin(), nodes.end());
  grid.offsets.push_back(static_cast<long>(grid.connectivity.size()));
  grid.types.push_back(type);
  grid.cell_where.push_back(Location{line, false});
}

/// Two tets on the unit cube's corners 0..4 sharing face 1 2 3, read from lines 10 and 11.
Grid two_tets() {
  Grid grid;
  grid.points = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
  grid.points_where = Location{3, false};
  add_cell(grid, 10, {0, 1, 2, 3}, 10);
  add_cell(grid, 10, {1, 2, 3, 4}, 11);
  return grid;
}

const InputCursor kFile("grid.vtk", "");

TEST(VtkCells, TetrahedraBecomeTet4Cells) {
  const Mesh mesh = build_mesh(kFile, two_tets());
  EXPECT_EQ(mesh.dim, 3);
  EXPECT_EQ(mesh.node_count(), 5);
  ASSERT_EQ(mesh.blocks.size(), 1u);
  EXPECT_STREQ(mesh.blocks[0].element->name, "tet4");
  EXPECT_EQ(mesh.blocks[0].connectivity, (std::vector<int>{0, 1, 2, 3, 1, 2, 3, 4}));
  EXPECT_EQ(mesh.blocks[0].source_ids, (std::vector<long>{0, 1}));
  EXPECT_TRUE(mesh.groups.empty());
  EXPECT_EQ(mesh.source, "grid.vtk");
}

TEST(VtkCells, EveryRegionValueIsAGroupAndLowerCellsAreItsFacets) {
  Grid grid = two_tets();
  add_cell(grid, 5, {1, 2, 3}, 12);  // the shared face as a triangle
  add_cell(grid, 3, {0, 1}, 13);     // an edge
  add_cell(grid, 1, {4}, 14);        // a vertex
  grid.regions = {7, 7, 2, 2, 9};
  const Mesh mesh = build_mesh(kFile, grid);
  EXPECT_EQ(mesh.cell_count(), 2);
  const Group* cells = mesh.group("region_7");
  ASSERT_NE(cells, nullptr);
  EXPECT_EQ(cells->cells, (std::vector<int>{0, 1}));
  EXPECT_EQ(cells->dim, 3);
  const Group* face = mesh.group("region_2");
  ASSERT_NE(face, nullptr);
  EXPECT_EQ(face->facets.count(), 1);
  EXPECT_TRUE(face->cells.empty());
  EXPECT_EQ(face->nodes, (std::vector<int>{0, 1, 2, 3}));  // the triangle's and the edge's
  const Group* vertex = mesh.group("region_9");
  ASSERT_NE(vertex, nullptr);
  EXPECT_EQ(vertex->nodes, (std::vector<int>{4}));
  EXPECT_EQ(vertex->dim, 0);
}

TEST(VtkCells, EveryRegisteredCellTypeIsRead) {
  // One cell of each type on its own nodes; quadratic and 2D types included.
  const std::vector<std::pair<long, int>> types = {{10, 4},  {12, 8},  {13, 6},  {14, 5}, {24, 10},
                                                   {25, 20}, {26, 15}, {27, 13}, {29, 27}};
  Grid grid;
  long next = 0;
  for (const auto& [type, nodes] : types) {
    std::vector<long> cell;
    for (int k = 0; k < nodes; ++k) {
      grid.points.insert(grid.points.end(), {double(next), double(k), double(k * k)});
      cell.push_back(next++);
    }
    add_cell(grid, type, cell, 20);
  }
  const Mesh mesh = build_mesh(kFile, grid);
  EXPECT_EQ(mesh.cell_count(), 9);
  EXPECT_EQ(mesh.blocks.size(), 9u);
  Grid plane;
  plane.points = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 0, 0};
  add_cell(plane, 9, {0, 1, 2, 3}, 5);
  add_cell(plane, 5, {1, 4, 2}, 6);
  const Mesh flat = build_mesh(kFile, plane);
  EXPECT_EQ(flat.dim, 2);
  EXPECT_EQ(flat.cell_count(), 2);
}

TEST(VtkCells, AnUnsupportedTypeIsNamedWithTheSupportedOnes) {
  Grid grid = two_tets();
  add_cell(grid, 7, {0, 1, 2}, 12);
  const std::string message = input_error([&] { build_mesh(kFile, grid); });
  EXPECT_EQ(message.rfind("grid.vtk:12: cell 2 has VTK type 7 (VTK_POLYGON), which is not supported; supported: "
                          "VTK_VERTEX (1), VTK_LINE (3), VTK_QUADRATIC_EDGE (21), ",
                          0),
            0u)
      << message;
  test_support::expect_contains(message, {"VTK_TETRA (10)", "VTK_QUADRATIC_TETRA (24)", "VTK_BIQUADRATIC_QUAD (28)",
                                          "VTK_TRIQUADRATIC_HEXAHEDRON (29)", "VTK_PYRAMID (14)"});
  EXPECT_EQ(message.find("VTK_POLYGON (7)"), std::string::npos) << message;
  grid = two_tets();
  add_cell(grid, 99, {0}, 12);
  EXPECT_EQ(input_error([&] { build_mesh(kFile, grid); }).rfind("grid.vtk:12: cell 2 has VTK type 99 (unknown)", 0),
            0u);
}

TEST(VtkCells, ACellWithTheWrongNodeCountIsNamed) {
  Grid grid;
  grid.points = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  add_cell(grid, 10, {0, 1, 2, 3}, 8);
  add_cell(grid, 10, {0, 1, 2}, 9);
  EXPECT_EQ(input_error([&] { build_mesh(kFile, grid); }), "grid.vtk:9: cell 1 (VTK_TETRA) has 3 nodes, expected 4");
  Grid binary;
  binary.points = grid.points;
  add_cell(binary, 9, {0, 1, 2}, 0);
  binary.cell_where[0] = Location{4096, true};
  EXPECT_EQ(input_error([&] { build_mesh(kFile, binary); }),
            "grid.vtk: byte 4096: cell 0 (VTK_QUAD) has 3 nodes, expected 4");
}

TEST(VtkCells, OffsetsMustRiseWithinTheConnectivity) {
  Grid grid = two_tets();
  const Location where{30, false};
  EXPECT_EQ(input_error([&] { check_offsets(kFile, grid, where); }), "");
  grid.offsets = {0, 5, 4, 8};
  grid.types.push_back(10);
  EXPECT_EQ(input_error([&] { check_offsets(kFile, grid, where); }),
            "grid.vtk:30: cell offsets are not increasing within the connectivity size (cell 1)");
  grid.offsets = {0, 9, 8};
  EXPECT_EQ(input_error([&] { check_offsets(kFile, grid, where); }),
            "grid.vtk:30: cell offsets are not increasing within the connectivity size (cell 0)");
  grid.offsets = {0, 4, 6};
  EXPECT_EQ(input_error([&] { check_offsets(kFile, grid, where); }),
            "grid.vtk:30: the offsets end at 6 but the connectivity has 8 entries");
  grid.offsets = {0, 4, 4, 8};  // an empty cell is in order
  EXPECT_EQ(input_error([&] { check_offsets(kFile, grid, where); }), "");
}

TEST(VtkCells, OffsetsAreCheckedFromTheGivenCellOn) {
  // A .vtu piece appends its cells: the cells before it were checked with their own piece.
  Grid grid = two_tets();
  grid.offsets = {0, 6, 4, 8};
  const Location where{0, false};
  EXPECT_EQ(input_error([&] { check_offsets(kFile, grid, where, 2); }), "");
  EXPECT_NE(input_error([&] { check_offsets(kFile, grid, where, 1); }), "");
}

TEST(VtkCells, IntegerValuesAreWholeFiniteAndExactAsLongs) {
  for (double value : {0.0, -0.0, 3.0, -4.0, 8.99e15, -8.99e15}) EXPECT_TRUE(is_integer_value(value)) << value;
  for (double value : {0.5, -2.25, 9.0e15, -9.0e15, 1e300, std::numeric_limits<double>::infinity(),
                       std::numeric_limits<double>::quiet_NaN()})
    EXPECT_FALSE(is_integer_value(value)) << value;
}

TEST(VtkCells, ToIntegersNamesTheArrayAndTheFirstBadIndex) {
  EXPECT_EQ(to_integers(kFile, {0, 4, 8, -1}, Location{2, false}, "offsets"), (std::vector<long>{0, 4, 8, -1}));
  EXPECT_EQ(input_error([] {
              to_integers(kFile, {0, 4, 4.5, 7.5}, Location{17, false}, "connectivity");
            }),
            "grid.vtk:17: connectivity value 2 is not an integer");
  EXPECT_EQ(input_error([] {
              to_integers(kFile, {NAN}, Location{64, true}, "types");
            }),
            "grid.vtk: byte 64: types value 0 is not an integer");
}

TEST(VtkCells, RegionArraysArePreferredByName) {
  EXPECT_EQ(region_priority("gmsh:physical"), 0);
  EXPECT_EQ(region_priority("region"), 1);
  EXPECT_EQ(region_priority("group"), 2);
  for (const char* other : {"Region", "gmsh:geometrical", "material", ""}) EXPECT_EQ(region_priority(other), -1);
}

}  // namespace
}  // namespace tensormass::detail::vtk
