// The node adjacency: every pair of nodes sharing a cell, sorted, and nothing else.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <utility>

#include "support/cantilever.hpp"
#include "tensormass/assembly/node_graph.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

TEST(NodeGraph, ListsExactlyTheNodesSharingACell) {
  const Mesh mesh = test::beam(3, "tet6", {3, 2, 2});
  const Model model(mesh, test::cantilever("hooke").model);
  const NodeGraph graph = make_node_graph(model);
  std::set<std::pair<int, int>> expected;
  for (int cell = 0; cell < model.cell_count(); ++cell)
    for (int a : model.cell_nodes(cell))
      for (int b : model.cell_nodes(cell)) expected.insert({a, b});
  std::set<std::pair<int, int>> listed;
  ASSERT_EQ(graph.node_count(), mesh.node_count());
  for (int node = 0; node < graph.node_count(); ++node) {
    const auto begin = graph.columns.begin() + graph.row_start[node],
               end = graph.columns.begin() + graph.row_start[node + 1];
    EXPECT_TRUE(std::is_sorted(begin, end));
    for (auto it = begin; it != end; ++it) {
      listed.insert({node, *it});
      EXPECT_EQ(graph.position(node, *it), it - graph.columns.begin());
    }
  }
  EXPECT_EQ(listed, expected);
  EXPECT_EQ(listed.size(), graph.columns.size());  // no duplicates
}

}  // namespace
}  // namespace tensormass
