// The mesh container (tensormass/mesh/mesh.hpp) on a hand-made mesh of two
// blocks: cells counted and located across blocks, cells described for
// messages, node groups chosen by position, and validate() naming each
// inconsistency it refuses.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace tensormass {
namespace {

/// A quad on [0,1]^2 (cell 0) and two triangles on [1,2]x[0,1] (cells 1, 2):
/// nodes 0 1 2 along y = 0 and 3 4 5 along y = 1.
Mesh two_block_mesh() {
  Mesh mesh;
  mesh.dim = 2;
  mesh.source = "plate.msh";
  mesh.rest_positions = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0};
  mesh.node_source_ids = {10, 11, 12, 13, 14, 15};
  ElementBlock quads;
  quads.element = Registry::instance().element("quad4");
  quads.connectivity = {0, 1, 4, 3};
  quads.source_ids = {100};
  ElementBlock triangles;
  triangles.element = Registry::instance().element("tri3");
  triangles.connectivity = {1, 2, 4, 2, 5, 4};
  triangles.source_ids = {200, 201};
  triangles.first_cell = 1;
  mesh.blocks = {quads, triangles};
  Group left;
  left.name = "left";
  left.dim = 1;
  left.nodes = {0, 3};
  mesh.groups.push_back(left);
  return mesh;
}

/// The message of the InputError validate() throws ("" when it throws none).
std::string validation_error(const Mesh& mesh) {
  try {
    mesh.validate();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(Mesh, CountsNodesAndCellsOfEveryBlock) {
  const Mesh mesh = two_block_mesh();
  EXPECT_EQ(mesh.node_count(), 6);
  EXPECT_EQ(mesh.cell_count(), 3);
  EXPECT_EQ(Mesh().cell_count(), 0);
  EXPECT_EQ(validation_error(mesh), "");
}

TEST(Mesh, LocateGivesTheBlockAndLocalIndexOfACell) {
  const Mesh mesh = two_block_mesh();
  EXPECT_EQ(mesh.locate(0), (std::pair<int, int>{0, 0}));
  EXPECT_EQ(mesh.locate(1), (std::pair<int, int>{1, 0}));
  EXPECT_EQ(mesh.locate(2), (std::pair<int, int>{1, 1}));
  EXPECT_EQ(mesh.locate(3), (std::pair<int, int>{-1, -1}));
  EXPECT_EQ(mesh.locate(-1), (std::pair<int, int>{-1, -1}));
}

TEST(Mesh, DescribeCellNamesItsNumberTypeAndSource) {
  Mesh mesh = two_block_mesh();
  EXPECT_EQ(mesh.describe_cell(0), "element 0 (quad4, id 100 in plate.msh)");
  EXPECT_EQ(mesh.describe_cell(2), "element 2 (tri3, id 201 in plate.msh)");
  EXPECT_EQ(mesh.describe_cell(7), "element 7");
  mesh.source.clear();
  EXPECT_EQ(mesh.describe_cell(1), "element 1 (tri3, id 200 in the mesh)");
  mesh.blocks[1].source_ids.clear();  // a mesh built in code
  EXPECT_EQ(mesh.describe_cell(1), "element 1 (tri3)");
}

TEST(Mesh, DescribeCellGivesTheNumberInTheWholeMeshOfAPart) {
  Mesh mesh = two_block_mesh();
  mesh.cell_numbers = {40, 41, 57};
  EXPECT_EQ(mesh.describe_cell(2), "element 57 (tri3, id 201 in plate.msh)");
  EXPECT_EQ(mesh.describe_cell(0), "element 40 (quad4, id 100 in plate.msh)");
}

TEST(Mesh, GroupFindsAGroupByName) {
  const Mesh mesh = two_block_mesh();
  ASSERT_NE(mesh.group("left"), nullptr);
  EXPECT_EQ(mesh.group("left")->nodes, (std::vector<int>{0, 3}));
  EXPECT_EQ(mesh.group("Left"), nullptr);
  EXPECT_EQ(mesh.group(""), nullptr);
}

TEST(Mesh, AddNodeGroupTakesTheNodesWherePositionsPassTheTest) {
  Mesh mesh = two_block_mesh();
  const Group& right = mesh.add_node_group("right", [](double x, double, double) { return x > 1.5; });
  EXPECT_EQ(right.name, "right");
  EXPECT_EQ(right.dim, 0);
  EXPECT_EQ(right.nodes, (std::vector<int>{2, 5}));
  EXPECT_TRUE(right.cells.empty());
  mesh.add_node_group("top", [](double, double y, double z) { return y == 1 && z == 0; });
  EXPECT_EQ(mesh.group("top")->nodes, (std::vector<int>{3, 4, 5}));
  EXPECT_TRUE(mesh.add_node_group("none", [](double, double, double) { return false; }).nodes.empty());
  EXPECT_EQ(mesh.groups.size(), 4u);
  EXPECT_EQ(validation_error(mesh), "");
}

TEST(MeshValidate, RefusesADimensionOtherThanTwoOrThree) {
  Mesh mesh = two_block_mesh();
  mesh.dim = 1;
  EXPECT_EQ(validation_error(mesh), "plate.msh: dimension 1 is not 2 or 3");
}

TEST(MeshValidate, RefusesPositionsNotInThrees) {
  Mesh mesh = two_block_mesh();
  mesh.rest_positions.push_back(0);
  EXPECT_EQ(validation_error(mesh), "plate.msh: positions are not n by 3");
}

TEST(MeshValidate, NamesANonFiniteCoordinateByTheNodesSourceId) {
  Mesh mesh = two_block_mesh();
  mesh.rest_positions[3 * 4 + 1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(validation_error(mesh), "plate.msh: node 14 has a non-finite coordinate");
  mesh.node_source_ids.clear();
  mesh.source.clear();
  EXPECT_EQ(validation_error(mesh), "mesh: node 4 has a non-finite coordinate");
  mesh.rest_positions[3 * 4 + 1] = 1;
  mesh.rest_positions[0] = -INFINITY;
  EXPECT_EQ(validation_error(mesh), "mesh: node 0 has a non-finite coordinate");
}

TEST(MeshValidate, RefusesBlocksWithoutElementOrOfAnotherDimension) {
  Mesh mesh = two_block_mesh();
  mesh.blocks[1].element = nullptr;
  EXPECT_EQ(validation_error(mesh), "plate.msh: element block without a reference element");
  mesh = two_block_mesh();
  mesh.dim = 3;
  EXPECT_EQ(validation_error(mesh), "plate.msh: quad4 cells in a 3D mesh");
}

TEST(MeshValidate, RefusesBlocksNumberedOutOfSequence) {
  Mesh mesh = two_block_mesh();
  mesh.blocks[1].first_cell = 2;
  EXPECT_EQ(validation_error(mesh), "plate.msh: block numbering is not contiguous");
  mesh.blocks[1].first_cell = 0;
  EXPECT_EQ(validation_error(mesh), "plate.msh: block numbering is not contiguous");
}

TEST(MeshValidate, RefusesConnectivityNotAMultipleOfTheNodeCount) {
  Mesh mesh = two_block_mesh();
  mesh.blocks[1].connectivity.push_back(0);
  EXPECT_EQ(validation_error(mesh), "plate.msh: tri3 connectivity is not a multiple of its node count");
}

TEST(MeshValidate, NamesTheCellThatRefersToAMissingNode) {
  Mesh mesh = two_block_mesh();
  mesh.blocks[1].connectivity[4] = 6;
  EXPECT_EQ(validation_error(mesh),
            "plate.msh: element 2 (tri3, id 201 in plate.msh) refers to node index 6, outside 0..5");
  mesh.blocks[1].connectivity[4] = -1;
  EXPECT_EQ(validation_error(mesh),
            "plate.msh: element 2 (tri3, id 201 in plate.msh) refers to node index -1, outside 0..5");
}

TEST(MeshValidate, RefusesAMeshWithoutCells) {
  Mesh mesh = two_block_mesh();
  mesh.blocks.clear();
  EXPECT_EQ(validation_error(mesh), "plate.msh: no 2D elements");
  mesh = two_block_mesh();
  mesh.blocks[0].connectivity.clear();
  mesh.blocks[1].connectivity.clear();
  mesh.blocks[1].first_cell = 0;
  EXPECT_EQ(validation_error(mesh), "plate.msh: no 2D elements");
}

TEST(MeshValidate, RefusesWholeMeshNumbersOfAnotherCount) {
  Mesh mesh = two_block_mesh();
  mesh.cell_numbers = {4, 5};
  EXPECT_EQ(validation_error(mesh), "plate.msh: 2 whole-mesh cell numbers for 3 cells");
  mesh.cell_numbers = {4, 5, 6};
  EXPECT_EQ(validation_error(mesh), "");
}

TEST(MeshValidate, NamesTheGroupThatRefersToAMissingNodeCellOrFacetNode) {
  Mesh mesh = two_block_mesh();
  mesh.groups[0].nodes.push_back(6);
  EXPECT_EQ(validation_error(mesh), "plate.msh: group 'left' refers to a missing node");
  mesh = two_block_mesh();
  mesh.groups[0].cells = {0, 3};
  EXPECT_EQ(validation_error(mesh), "plate.msh: group 'left' refers to a missing element");
  mesh = two_block_mesh();
  mesh.groups[0].facets.nodes = {0, -3};
  mesh.groups[0].facets.offsets = {0, 2};
  mesh.groups[0].facets.orders = {1};
  EXPECT_EQ(validation_error(mesh), "plate.msh: group 'left' has a facet on a missing node");
}

}  // namespace
}  // namespace tensormass
