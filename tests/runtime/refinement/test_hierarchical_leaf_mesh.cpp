// The leaf mesh a hierarchy rebuilds after each change (hierarchical_leaf_mesh.cpp
// behind tensormass/refinement/hierarchical_mesh.hpp): nodes no cell uses
// are removed with the later ones moving down in order, whole leaves are
// their hierarchy cells, transition cells fill their owner, and groups of
// cells follow the leaves. (Splitting, balance, conformity, node groups and
// facets: test_hierarchical_mesh.cpp, test_hierarchical_mesh_3d.cpp; field
// transfer: test_leaf_transfer.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <string>
#include <vector>

#include "refinement_checks.hpp"
#include "support/cantilever.hpp"
#include "tensormass/refinement/hierarchical_mesh.hpp"

namespace tensormass {
namespace {

using Position = std::array<double, 3>;

std::vector<Position> node_positions(const Mesh& mesh) {
  std::vector<Position> positions;
  for (int n = 0; n < mesh.node_count(); ++n)
    positions.push_back({mesh.rest_positions[3 * n], mesh.rest_positions[3 * n + 1], mesh.rest_positions[3 * n + 2]});
  return positions;
}

/// The leaf-mesh cells owned by original cell `origin`.
std::vector<int> cells_of_origin(const HierarchicalMesh& hierarchy, int origin) {
  std::vector<int> cells;
  for (int cell = 0; cell < hierarchy.leaf_mesh().cell_count(); ++cell)
    if (hierarchy.hierarchy_cell(hierarchy.leaf_owners()[cell]).origin == origin) cells.push_back(cell);
  return cells;
}

/// The nodes of leaf-mesh cell `cell`.
std::vector<int> leaf_cell_nodes(const Mesh& mesh, int cell) {
  const auto [block, local] = mesh.locate(cell);
  const auto nodes = mesh.blocks[block].cell_nodes(local);
  return {nodes.begin(), nodes.end()};
}

TEST(HierarchicalLeafMesh, RemovedNodesLetTheLaterOnesMoveDownInOrder) {
  const Mesh original = test::beam(2, "quad4", {4, 1, 1});
  HierarchicalMesh hierarchy(original);
  hierarchy.refine(cells_of_origin(hierarchy, 0));
  hierarchy.refine(cells_of_origin(hierarchy, 3));
  const std::vector<Position> before = node_positions(hierarchy.leaf_mesh());
  const LeafTransfer transfer = hierarchy.coarsen(cells_of_origin(hierarchy, 0));
  const std::vector<Position> after = node_positions(hierarchy.leaf_mesh());
  ASSERT_LT(after.size(), before.size());
  // The original nodes first, in their order.
  const std::vector<Position> originals = node_positions(original);
  ASSERT_GE(after.size(), originals.size());
  EXPECT_TRUE(std::equal(originals.begin(), originals.end(), after.begin()));
  // The others: those of before still used, in the order they had.
  std::size_t at = 0;
  for (const Position& p : after) {
    while (at < before.size() && before[at] != p) ++at;
    ASSERT_LT(at, before.size()) << "a node out of order or new after coarsening: " << p[0] << " " << p[1];
    ++at;
  }
  // Each kept node carries its old value alone.
  ASSERT_EQ(transfer.new_node_count(), static_cast<int>(after.size()));
  for (int n = 0; n < transfer.new_node_count(); ++n) {
    ASSERT_EQ(transfer.node_offsets[n + 1] - transfer.node_offsets[n], 1) << n;
    const int source = transfer.node_sources[transfer.node_offsets[n]];
    EXPECT_EQ(transfer.node_weights[transfer.node_offsets[n]], 1.0);
    EXPECT_EQ(before[source], after[n]) << n;
  }
}

TEST(HierarchicalLeafMesh, AWholeLeafIsItsHierarchyCell) {
  for (const Mesh& original : {refinement_test::mixed_beam(), test::beam(3, "tet6", {3, 1, 1})}) {
    HierarchicalMesh hierarchy(original);
    hierarchy.refine(std::vector<int>{0, 1});
    hierarchy.refine(std::vector<int>{0});
    const Mesh& leaf = hierarchy.leaf_mesh();
    int whole = 0;
    for (int cell = 0; cell < leaf.cell_count(); ++cell) {
      const HierarchyCell& owner = hierarchy.hierarchy_cell(hierarchy.leaf_owners()[cell]);
      EXPECT_TRUE(owner.is_leaf());
      EXPECT_EQ(hierarchy.leaf_levels()[cell], owner.level);
      if (hierarchy.leaf_transitions()[cell]) continue;
      ++whole;
      const auto [block, local] = leaf.locate(cell);
      EXPECT_EQ(leaf.blocks[block].element, owner.element) << cell;
      const std::vector<int> corners(owner.corners.begin(), owner.corners.begin() + owner.corner_count());
      EXPECT_EQ(leaf_cell_nodes(leaf, cell), corners) << cell;
    }
    EXPECT_GT(whole, 0);
  }
}

TEST(HierarchicalLeafMesh, TransitionCellsFillTheirOwnerAndUseItsCentre) {
  const Mesh original = test::beam(2, "quad4", {3, 1, 1});
  HierarchicalMesh hierarchy(original);
  hierarchy.refine(std::vector<int>{1});  // the middle square: both neighbours get a hanging midpoint
  const Mesh& leaf = hierarchy.leaf_mesh();
  std::set<int> owners;
  for (int cell = 0; cell < leaf.cell_count(); ++cell) {
    if (!hierarchy.leaf_transitions()[cell]) continue;
    const int owner = hierarchy.leaf_owners()[cell];
    owners.insert(owner);
    const HierarchyCell& c = hierarchy.hierarchy_cell(owner);
    ASSERT_GE(c.centre, 0) << "a transition fills a leaf with a centre node";
    const std::vector<int> nodes = leaf_cell_nodes(leaf, cell);
    EXPECT_NE(std::find(nodes.begin(), nodes.end(), c.centre), nodes.end()) << "fans around the centre";
    EXPECT_STREQ(leaf.blocks[leaf.locate(cell).first].element->name, "tri3");
  }
  EXPECT_EQ(owners, (std::set<int>{0, 2}));
  // The fans of each neighbour cover its square.
  for (int owner : owners) {
    double area = 0;
    for (int cell = 0; cell < leaf.cell_count(); ++cell)
      if (hierarchy.leaf_owners()[cell] == owner) area += refinement_test::cell_area(leaf, cell);
    EXPECT_NEAR(area, 1.0, 1e-14) << owner;
  }
  refinement_test::expect_valid_leaf_mesh(hierarchy, "middle square refined");
}

TEST(HierarchicalLeafMesh, GroupsOfCellsHoldTheLeavesOfTheirCells) {
  HierarchicalMesh hierarchy(refinement_test::mixed_beam());
  hierarchy.refine(std::vector<int>{0, 5, 20});
  hierarchy.refine(std::vector<int>{3});
  const Mesh& leaf = hierarchy.leaf_mesh();
  const Mesh& original = hierarchy.original_mesh();
  for (const char* name : {"body", "phase_tri3", "phase_quad4"}) {
    const Group* group = leaf.group(name);
    const Group* was = original.group(name);
    ASSERT_TRUE(group && was) << name;
    std::vector<int> expected;
    for (int cell = 0; cell < leaf.cell_count(); ++cell) {
      const int origin = hierarchy.hierarchy_cell(hierarchy.leaf_owners()[cell]).origin;
      if (std::binary_search(was->cells.begin(), was->cells.end(), origin)) expected.push_back(cell);
    }
    EXPECT_EQ(group->cells, expected) << name;
  }
  EXPECT_EQ(static_cast<int>(leaf.group("body")->cells.size()), leaf.cell_count());
}

}  // namespace
}  // namespace tensormass
