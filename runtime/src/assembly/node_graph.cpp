#include "tensormass/assembly/node_graph.hpp"

#include <algorithm>
#include <cassert>

namespace tensormass {

int NodeGraph::position(int node, int neighbour) const {
  const auto begin = columns.begin() + row_start[node], end = columns.begin() + row_start[node + 1];
  const auto found = std::lower_bound(begin, end, neighbour);
  assert(found != end && *found == neighbour);
  return static_cast<int>(found - columns.begin());
}

NodeGraph make_node_graph(const Model& model, const NodalPressure* nodal) {
  std::vector<std::vector<int>> neighbours(model.mesh().node_count());
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const auto nodes = model.cell_nodes(cell);
    for (int a : nodes) neighbours[a].insert(neighbours[a].end(), nodes.begin(), nodes.end());
  }
  for (int patch = 0; nodal && patch < nodal->patch_count(); ++patch) {
    const auto nodes = nodal->patch_nodes(patch);
    for (int a : nodes) neighbours[a].insert(neighbours[a].end(), nodes.begin(), nodes.end());
  }
  NodeGraph graph;
  graph.row_start.assign(1, 0);
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    graph.columns.insert(graph.columns.end(), list.begin(), list.end());
    graph.row_start.push_back(static_cast<int>(graph.columns.size()));
    std::vector<int>().swap(list);
  }
  return graph;
}

}  // namespace tensormass
