// HierarchicalMesh on a mixed quad4/tri3 beam: conformity, 2:1 balance and
// area after random refinements and coarsenings, bitwise restoration of the
// original mesh, groups and facets, bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "refinement_checks.hpp"
#include "tensormass/common/errors.hpp"

namespace {

using refinement_test::all_cells;
using refinement_test::expect_same_mesh;
using refinement_test::expect_valid_leaf_mesh;
using refinement_test::mixed_beam;
using refinement_test::position;
using tensormass::HierarchicalMesh;
using tensormass::Mesh;

/// The leaf-mesh cells whose owner lies in the original cell `origin`.
std::vector<int> cells_of_origin(const HierarchicalMesh& hierarchy, int origin) {
  std::vector<int> cells;
  for (int cell = 0; cell < hierarchy.leaf_mesh().cell_count(); ++cell)
    if (hierarchy.hierarchy_cell(hierarchy.leaf_owners()[cell]).origin == origin) cells.push_back(cell);
  return cells;
}

/// Coarsens everything until nothing changes; returns the number of calls.
int coarsen_all(HierarchicalMesh& hierarchy) {
  int calls = 0;
  for (int before = -1; before != hierarchy.hierarchy_size(); ++calls) {
    before = hierarchy.hierarchy_size();
    hierarchy.coarsen(all_cells(hierarchy.leaf_mesh()));
  }
  return calls;
}

TEST(HierarchicalMesh, WrapsTheOriginalUnchanged) {
  const Mesh original = mixed_beam();
  const HierarchicalMesh hierarchy(original);
  expect_same_mesh(hierarchy.leaf_mesh(), original);
  EXPECT_EQ(hierarchy.hierarchy_size(), original.cell_count());
  for (int level : hierarchy.leaf_levels()) EXPECT_EQ(level, 0);
  EXPECT_EQ(hierarchy.leaves_per_level(), std::vector<int>{original.cell_count()});
}

TEST(HierarchicalMesh, QuadAndTriangleSplitIntoFourChildrenOfAQuarterArea) {
  const Mesh original = mixed_beam(2, 1);  // two triangles (x < 1), one quad
  ASSERT_EQ(original.cell_count(), 3);
  HierarchicalMesh hierarchy(original);
  const std::vector<int> all{0, 1, 2};
  hierarchy.refine(all);
  const Mesh& mesh = hierarchy.leaf_mesh();
  EXPECT_EQ(mesh.cell_count(), 12);
  EXPECT_EQ(hierarchy.leaves_per_level(), (std::vector<int>{0, 12}));
  // 6 corners + 8 edge midpoints (7 grid edges and the diagonal) + 1 quad centre.
  EXPECT_EQ(mesh.node_count(), 6 + 8 + 1);
  for (int cell = 0; cell < mesh.cell_count(); ++cell) {
    const tensormass::HierarchyCell& leaf = hierarchy.hierarchy_cell(hierarchy.leaf_owners()[cell]);
    const tensormass::HierarchyCell& parent = hierarchy.hierarchy_cell(leaf.parent);
    EXPECT_EQ(leaf.level, 1);
    EXPECT_EQ(leaf.element, parent.element);
    EXPECT_DOUBLE_EQ(refinement_test::cell_area(mesh, cell), refinement_test::cell_area(original, leaf.origin) / 4);
  }
  // Child k keeps corner k of its parent.
  for (int parent = 0; parent < 3; ++parent)
    for (int k = 0; k < hierarchy.hierarchy_cell(parent).corner_count(); ++k)
      EXPECT_EQ(hierarchy.hierarchy_cell(hierarchy.hierarchy_cell(parent).children[k]).corners[k],
                hierarchy.hierarchy_cell(parent).corners[k]);
  expect_valid_leaf_mesh(hierarchy, "uniform");
}

TEST(HierarchicalMesh, NeighboursOfARefinedCellGetTransitionTriangles) {
  HierarchicalMesh hierarchy(mixed_beam());
  // Refine one quad in the middle of the quad half and one triangle.
  ASSERT_EQ(hierarchy.leaf_mesh().blocks[0].element->name, std::string("quad4"));
  const std::vector<int> marked{4, hierarchy.leaf_mesh().cell_count() - 5};
  hierarchy.refine(marked);
  int transitions = 0;
  for (char transition : hierarchy.leaf_transitions()) transitions += transition;
  EXPECT_GT(transitions, 0);
  expect_valid_leaf_mesh(hierarchy, "one refinement");
}

TEST(HierarchicalMesh, RepeatedRefinementOfOneCornerKeepsTwoToOneBalance) {
  HierarchicalMesh hierarchy(mixed_beam());
  for (int round = 0; round < 5; ++round) {
    // The leaf-mesh cell holding the corner (0, 0).
    const Mesh& mesh = hierarchy.leaf_mesh();
    int corner_cell = -1;
    for (int cell = 0; cell < mesh.cell_count() && corner_cell < 0; ++cell) {
      const auto [b, local] = mesh.locate(cell);
      for (int node : mesh.blocks[b].cell_nodes(local))
        if (position(mesh, node)[0] == 0.0 && position(mesh, node)[1] == 0.0) corner_cell = cell;
    }
    ASSERT_GE(corner_cell, 0);
    const std::vector<int> marked{corner_cell};
    hierarchy.refine(marked);
    expect_valid_leaf_mesh(hierarchy, ("round " + std::to_string(round)).c_str());
  }
  const std::vector<int> counts = hierarchy.leaves_per_level();
  EXPECT_EQ(counts.size(), 6u);  // levels 0 .. 5
  // Balance forced refinement around the corner: more than the marked chain.
  EXPECT_GT(counts[2] + counts[3] + counts[4], 3 * 3);
}

TEST(HierarchicalMesh, MaxLevelStopsRefinement) {
  HierarchicalMesh hierarchy(mixed_beam());
  for (int round = 0; round < 4; ++round) hierarchy.refine(all_cells(hierarchy.leaf_mesh()), 2);
  for (int level : hierarchy.leaf_levels()) EXPECT_EQ(level, 2);
  expect_valid_leaf_mesh(hierarchy, "max level 2");
}

TEST(HierarchicalMesh, RandomRefinementsAndCoarseningsStayConformingAndComeBack) {
  const Mesh original = mixed_beam();
  HierarchicalMesh hierarchy(original);
  std::mt19937 random(12345);
  int refined = 0, coarsened = 0;
  for (int step = 0; step < 40; ++step) {
    const Mesh& mesh = hierarchy.leaf_mesh();
    std::vector<int> marked;
    std::bernoulli_distribution pick(step % 3 == 2 ? 0.7 : 0.15);
    for (int cell = 0; cell < mesh.cell_count(); ++cell)
      if (pick(random)) marked.push_back(cell);
    const int before = hierarchy.hierarchy_size();
    if (step % 3 == 2) {
      hierarchy.coarsen(marked);
      coarsened += hierarchy.hierarchy_size() < before;
    } else {
      hierarchy.refine(marked, 4);
      refined += hierarchy.hierarchy_size() > before;
    }
    expect_valid_leaf_mesh(hierarchy, ("step " + std::to_string(step)).c_str());
    if (testing::Test::HasFailure()) return;
  }
  EXPECT_GT(refined, 10);
  EXPECT_GT(coarsened, 5);
  EXPECT_GT(hierarchy.leaves_per_level().size(), 3u);
  coarsen_all(hierarchy);
  expect_same_mesh(hierarchy.leaf_mesh(), original);
  EXPECT_EQ(hierarchy.hierarchy_size(), original.cell_count());
}

TEST(HierarchicalMesh, RefineThenCoarsenGivesBackTheOriginalMesh) {
  const Mesh original = mixed_beam();
  HierarchicalMesh hierarchy(original);
  hierarchy.refine(std::vector<int>{0, 3, 20, 26});  // of 9 quads and 18 triangles
  ASSERT_GT(hierarchy.leaf_mesh().cell_count(), original.cell_count());
  EXPECT_EQ(coarsen_all(hierarchy), 2);  // one merge, then nothing left
  expect_same_mesh(hierarchy.leaf_mesh(), original);
}

TEST(HierarchicalMesh, CoarseningWaitsForAllSiblingsAndForBalance) {
  HierarchicalMesh hierarchy(mixed_beam());
  hierarchy.refine(std::vector<int>{0});
  const std::vector<int> children = cells_of_origin(hierarchy, 0);
  ASSERT_EQ(children.size(), 4u);
  // Three of the four siblings: nothing merges.
  const int size = hierarchy.hierarchy_size();
  hierarchy.coarsen(std::vector<int>(children.begin(), children.begin() + 3));
  EXPECT_EQ(hierarchy.hierarchy_size(), size);
  // Quad 1 lies on quad 0 (the beam numbers cells column by column). Split
  // it, then its child 0, which holds the corner on the shared edge: level 2
  // along quad 0's top edge, so quad 0's children cannot merge yet.
  hierarchy.refine(std::vector<int>{cells_of_origin(hierarchy, 1)[0]});
  hierarchy.refine(std::vector<int>{cells_of_origin(hierarchy, 1)[0]});
  expect_valid_leaf_mesh(hierarchy, "level 2 above cell 0");
  const int before = hierarchy.hierarchy_size();
  hierarchy.coarsen(cells_of_origin(hierarchy, 0));
  EXPECT_EQ(hierarchy.hierarchy_size(), before) << "merging would put level 0 next to level 2";
  expect_valid_leaf_mesh(hierarchy, "blocked coarsening");
  // Once quad 1 is back to level 1, quad 0 merges.
  hierarchy.coarsen(cells_of_origin(hierarchy, 1));
  hierarchy.coarsen(cells_of_origin(hierarchy, 0));
  EXPECT_TRUE(hierarchy.hierarchy_cell(0).is_leaf());  // a fan: quad 1's children split its top edge
  EXPECT_EQ(cells_of_origin(hierarchy, 0).size(), 5u);
  EXPECT_FALSE(hierarchy.hierarchy_cell(1).is_leaf());
  expect_valid_leaf_mesh(hierarchy, "after unblocking");
}

TEST(HierarchicalMesh, NodeGroupsAndFacetsFollowTheSplitEdges) {
  HierarchicalMesh hierarchy(mixed_beam());
  // Refine every cell touching x = 0 (clamp) or y = 0 (bottom), twice.
  for (int round = 0; round < 2; ++round) {
    const Mesh& mesh = hierarchy.leaf_mesh();
    std::vector<int> marked;
    for (int cell = 0; cell < mesh.cell_count(); ++cell) {
      const auto [b, local] = mesh.locate(cell);
      for (int node : mesh.blocks[b].cell_nodes(local))
        if (position(mesh, node)[0] == 0.0 || position(mesh, node)[1] == 0.0) marked.push_back(cell);
    }
    hierarchy.refine(marked);
  }
  const Mesh& mesh = hierarchy.leaf_mesh();
  expect_valid_leaf_mesh(hierarchy, "boundary refinement");
  const auto nodes_where = [&](auto inside) {
    std::vector<int> nodes;
    for (int node = 0; node < mesh.node_count(); ++node)
      if (inside(position(mesh, node))) nodes.push_back(node);
    return nodes;
  };
  const std::vector<int> at_clamp = nodes_where([](const double* x) { return x[0] == 0.0; });
  const std::vector<int> at_bottom = nodes_where([](const double* x) { return x[1] == 0.0; });
  const std::vector<int> at_tip = nodes_where([](const double* x) { return x[0] == 6.0; });
  EXPECT_EQ(at_clamp.size(), 3u * 4 + 1);  // 3 original edges split twice
  EXPECT_EQ(mesh.group("clamp")->nodes, at_clamp);
  EXPECT_EQ(mesh.group("bottom")->nodes, at_bottom);
  EXPECT_EQ(mesh.group("tip")->nodes, at_tip);
  EXPECT_EQ(mesh.group("body")->nodes, nodes_where([](const double*) { return true; }));
  EXPECT_EQ(mesh.group("body")->cells, all_cells(mesh));
  // Clamp facets: the boundary edges at x = 0, each once, in the original facets' direction.
  const tensormass::FacetSet& facets = mesh.group("clamp")->facets;
  const tensormass::FacetSet& original_facets = hierarchy.original_mesh().group("clamp")->facets;
  ASSERT_EQ(facets.count(), 12);
  const double direction = position(mesh, original_facets.nodes[1])[1] - position(mesh, original_facets.nodes[0])[1];
  double length = 0;
  for (int f = 0; f < facets.count(); ++f) {
    const int a = facets.nodes[facets.offsets[f]], b = facets.nodes[facets.offsets[f] + 1];
    EXPECT_EQ(position(mesh, a)[0], 0.0);
    EXPECT_EQ(position(mesh, b)[0], 0.0);
    EXPECT_GT((position(mesh, b)[1] - position(mesh, a)[1]) * direction, 0.0) << "facet " << f;
    length += refinement_test::edge_length(mesh, a, b);
  }
  EXPECT_DOUBLE_EQ(length, 3.0);
  // Phase groups keep their cells' children and transition triangles.
  for (const char* phase : {"phase_tri3", "phase_quad4"}) {
    const tensormass::Group& group = *mesh.group(phase);
    const tensormass::Group& before = *hierarchy.original_mesh().group(phase);
    for (int cell = 0; cell < mesh.cell_count(); ++cell) {
      const int origin = hierarchy.hierarchy_cell(hierarchy.leaf_owners()[cell]).origin;
      const bool in_original = std::binary_search(before.cells.begin(), before.cells.end(), origin);
      EXPECT_EQ(std::binary_search(group.cells.begin(), group.cells.end(), cell), in_original) << phase << " " << cell;
    }
  }
}

TEST(HierarchicalMesh, BadInputIsAnInputErrorThatSaysWhy) {
  tensormass::BeamSpec quadratic;
  quadratic.cells = {2, 1, 1};
  quadratic.order = 2;
  refinement_test::expect_input_error([&] { (void)HierarchicalMesh(tensormass::make_beam(quadratic)); },
                                      "quad8 cells cannot be refined");
  Mesh clockwise = mixed_beam();
  std::reverse(clockwise.blocks[0].connectivity.begin(), clockwise.blocks[0].connectivity.begin() + 4);
  refinement_test::expect_input_error([&] { (void)HierarchicalMesh(clockwise); }, "clockwise");

  HierarchicalMesh hierarchy(mixed_beam());
  const int count = hierarchy.leaf_mesh().cell_count();
  refinement_test::expect_input_error([&] { hierarchy.refine(std::vector<int>{count}); },
                                      "is not a cell of the leaf mesh");
  refinement_test::expect_input_error([&] { hierarchy.refine(std::vector<int>{-1}); }, "refine: cell -1");
  refinement_test::expect_input_error([&] { hierarchy.coarsen(std::vector<int>{count + 3}); }, "coarsen: cell");
  refinement_test::expect_input_error([&] { hierarchy.refine(std::vector<int>{0}, -1); }, "max_level");
  EXPECT_EQ(hierarchy.leaf_mesh().cell_count(), count);  // nothing changed
}

}  // namespace
