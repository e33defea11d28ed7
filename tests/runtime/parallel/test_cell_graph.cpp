// The cell graph the mesh partitioner reads (make_cell_graph in
// tensormass/parallel/cell_partition.hpp): cells sharing a face (3D) or an
// edge (2D) are neighbours, cells meeting at a corner or an edge (3D) are
// not, on first- and second-order meshes alike (corners count, mid-edge
// nodes do not), rows are sorted and numbered mesh-wide across blocks.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <vector>

#include "support/cantilever.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/parallel/cell_partition.hpp"

namespace tensormass {
namespace {

using Rows = std::vector<std::vector<int>>;

/// The graph's rows as lists of neighbours.
Rows rows_of(const parallel::CellGraph& graph) {
  Rows rows;
  for (std::size_t cell = 0; cell + 1 < graph.row_start.size(); ++cell)
    rows.emplace_back(graph.columns.begin() + graph.row_start[cell], graph.columns.begin() + graph.row_start[cell + 1]);
  return rows;
}

/// Neighbours found by comparing every pair of cells: `dim` nodes or more in common.
Rows shared_node_pairs(const Mesh& mesh) {
  std::vector<std::set<int>> nodes;
  for (const ElementBlock& block : mesh.blocks)
    for (int local = 0; local < block.count(); ++local)
      nodes.emplace_back(block.cell_nodes(local).begin(), block.cell_nodes(local).end());
  Rows rows(nodes.size());
  for (std::size_t a = 0; a < nodes.size(); ++a)
    for (std::size_t b = 0; b < nodes.size(); ++b) {
      if (a == b) continue;
      int common = 0;
      for (int node : nodes[a]) common += static_cast<int>(nodes[b].count(node));
      if (common >= mesh.dim) rows[a].push_back(static_cast<int>(b));
    }
  return rows;
}

/// A block of `element` cells with the given corners, numbered from `first_cell`.
ElementBlock block_of(const char* element, std::vector<int> connectivity, int first_cell) {
  ElementBlock block;
  block.element = Registry::instance().element(element);
  block.connectivity = std::move(connectivity);
  block.first_cell = first_cell;
  return block;
}

/// Nodes of an (nx+1) by (ny+1) by (nz+1) grid of unit spacing, node (i, j, k) numbered i + (nx+1) (j + (ny+1) k).
std::vector<double> grid_nodes(int nx, int ny, int nz) {
  std::vector<double> positions;
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) positions.insert(positions.end(), {double(i), double(j), double(k)});
  return positions;
}

TEST(CellGraph, QuadsSharingAnEdgeAreNeighboursAndQuadsMeetingAtACornerAreNot) {
  // 2 x 2 quads: 0 1 below, 2 3 above; 0 and 3 meet at the centre node only.
  Mesh mesh;
  mesh.dim = 2;
  mesh.rest_positions = grid_nodes(2, 2, 0);
  mesh.blocks.push_back(block_of("quad4", {0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7}, 0));
  const parallel::CellGraph graph = parallel::make_cell_graph(mesh);
  EXPECT_EQ(graph.row_start, (std::vector<int>{0, 2, 4, 6, 8}));
  EXPECT_EQ(rows_of(graph), (Rows{{1, 2}, {0, 3}, {0, 3}, {1, 2}}));
}

TEST(CellGraph, HexesSharingOnlyAnEdgeAreNotNeighbours) {
  // 2 x 2 x 1 hexes: 0 and 3 (and 1 and 2) share the vertical edge at the centre.
  Mesh mesh;
  mesh.rest_positions = grid_nodes(2, 2, 1);
  std::vector<int> connectivity;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int n = i + 3 * j;
      connectivity.insert(connectivity.end(), {n, n + 1, n + 4, n + 3, n + 9, n + 10, n + 13, n + 12});
    }
  mesh.blocks.push_back(block_of("hex8", connectivity, 0));
  EXPECT_EQ(rows_of(parallel::make_cell_graph(mesh)), (Rows{{1, 2}, {0, 3}, {0, 3}, {1, 2}}));
}

TEST(CellGraph, CellsOfSeveralBlocksAreNumberedMeshWide) {
  // A quad on [0,1]^2 (cell 0) and two triangles on [1,2]x[0,1] (cells 1, 2).
  Mesh mesh;
  mesh.dim = 2;
  mesh.rest_positions = grid_nodes(2, 1, 0);  // 0 1 2 / 3 4 5
  mesh.blocks.push_back(block_of("quad4", {0, 1, 4, 3}, 0));
  mesh.blocks.push_back(block_of("tri3", {1, 2, 4, 2, 5, 4}, 1));
  EXPECT_EQ(rows_of(parallel::make_cell_graph(mesh)), (Rows{{1}, {0, 2}, {1}}));
}

TEST(CellGraph, ALoneCellHasNoNeighbours) {
  Mesh mesh;
  mesh.dim = 2;
  mesh.rest_positions = grid_nodes(1, 1, 0);
  mesh.blocks.push_back(block_of("quad4", {0, 1, 3, 2}, 0));
  const parallel::CellGraph graph = parallel::make_cell_graph(mesh);
  EXPECT_EQ(graph.row_start, (std::vector<int>{0, 0}));
  EXPECT_TRUE(graph.columns.empty());
}

TEST(CellGraph, EqualsThePairsOfCellsSharingAFaceInTetrahedra) {
  for (const char* cut : {"tet6", "tet5"}) {
    const Mesh mesh = test::beam(3, cut, {3, 2, 2});
    const Rows rows = rows_of(parallel::make_cell_graph(mesh));
    EXPECT_EQ(rows, shared_node_pairs(mesh)) << cut;
    for (const auto& row : rows) {
      EXPECT_TRUE(std::is_sorted(row.begin(), row.end())) << cut;
      EXPECT_LE(row.size(), 4u) << cut;  // a tet has four faces
    }
  }
}

TEST(CellGraph, EqualsThePairsOfCellsSharingAnEdgeInTriangles) {
  const Mesh mesh = test::beam(2, "tri3", {4, 3, 1});
  const Rows rows = rows_of(parallel::make_cell_graph(mesh));
  EXPECT_EQ(rows, shared_node_pairs(mesh));
  int edges = 0;
  for (const auto& row : rows) edges += static_cast<int>(row.size());
  // 4 x 3 squares of 2 triangles: 12 diagonals, 3 x 3 vertical and 4 x 2 horizontal inner edges.
  EXPECT_EQ(edges, 2 * (12 + 9 + 8));
}

// A second-order cell shares an edge's mid-edge node with its edge
// neighbours: only corners count, so the graph is the first-order mesh's.
TEST(CellGraph, SecondOrderCellsHaveTheGraphOfTheirCorners) {
  for (const char* cut : {"tet6", "hex8", "prism6"}) {
    const Mesh linear = test::beam(3, cut, {2, 2, 2});
    const Mesh quadratic = test::beam(3, cut, {2, 2, 2}, 2);
    ASSERT_GT(quadratic.blocks[0].nodes_per_cell(), linear.blocks[0].nodes_per_cell()) << cut;
    EXPECT_EQ(rows_of(parallel::make_cell_graph(quadratic)), rows_of(parallel::make_cell_graph(linear))) << cut;
  }
  const Mesh tri6 = test::beam(2, "tri3", {3, 2, 1}, 2);
  EXPECT_EQ(rows_of(parallel::make_cell_graph(tri6)),
            rows_of(parallel::make_cell_graph(test::beam(2, "tri3", {3, 2, 1}))));
}

}  // namespace
}  // namespace tensormass
