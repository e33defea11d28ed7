#include <algorithm>

#include "tensormass/parallel/cell_partition.hpp"

namespace tensormass::parallel {

CellGraph make_cell_graph(const Model& model) {
  const int cells = model.cell_count(), nodes = model.mesh().node_count(), d = model.dim();
  std::vector<int> node_start(nodes + 1, 0), node_cells;
  for (int cell = 0; cell < cells; ++cell)
    for (int node : model.cell_nodes(cell)) ++node_start[node + 1];
  for (int n = 0; n < nodes; ++n) node_start[n + 1] += node_start[n];
  node_cells.resize(node_start[nodes]);
  std::vector<int> next(node_start.begin(), node_start.end() - 1);
  for (int cell = 0; cell < cells; ++cell)
    for (int node : model.cell_nodes(cell)) node_cells[next[node]++] = cell;
  CellGraph graph;
  graph.row_start.assign(1, 0);
  std::vector<int> shared(cells, 0), touched;
  for (int cell = 0; cell < cells; ++cell) {
    touched.clear();
    for (int node : model.cell_nodes(cell))
      for (int k = node_start[node]; k < node_start[node + 1]; ++k) {
        const int other = node_cells[k];
        if (other == cell) continue;
        if (shared[other]++ == 0) touched.push_back(other);
      }
    std::sort(touched.begin(), touched.end());
    for (int other : touched) {
      if (shared[other] >= d) graph.columns.push_back(other);
      shared[other] = 0;
    }
    graph.row_start.push_back(static_cast<int>(graph.columns.size()));
  }
  return graph;
}

}  // namespace tensormass::parallel
