#include <algorithm>
#include <span>

#include "tensormass/parallel/cell_partition.hpp"

namespace tensormass::parallel {

namespace {

/// A cell's corners: its first corner_count nodes. Neighbours are counted by
/// shared corners, so that cells of a second-order mesh sharing only an
/// edge (two corners and its mid-edge node) are not taken for face neighbours.
std::span<const int> cell_corners(const ElementBlock& block, int local) {
  return block.cell_nodes(local).first(static_cast<std::size_t>(block.element->corner_count));
}

/// Calls visit(cell, corner) for every corner of every cell, cells in order.
template <class Visit>
void for_each_cell_corner(const Mesh& mesh, Visit visit) {
  for (const ElementBlock& block : mesh.blocks)
    for (int local = 0; local < block.count(); ++local)
      for (int node : cell_corners(block, local)) visit(block.first_cell + local, node);
}

}  // namespace

CellGraph make_cell_graph(const Mesh& mesh) {
  const int cells = mesh.cell_count(), nodes = mesh.node_count(), d = mesh.dim;
  std::vector<int> node_start(nodes + 1, 0), node_cells;
  for_each_cell_corner(mesh, [&](int, int node) { ++node_start[node + 1]; });
  for (int n = 0; n < nodes; ++n) node_start[n + 1] += node_start[n];
  node_cells.resize(node_start[nodes]);
  std::vector<int> next(node_start.begin(), node_start.end() - 1);
  for_each_cell_corner(mesh, [&](int cell, int node) { node_cells[next[node]++] = cell; });
  CellGraph graph;
  graph.row_start.assign(1, 0);
  std::vector<int> shared(cells, 0), touched;
  for (const ElementBlock& block : mesh.blocks)
    for (int local = 0; local < block.count(); ++local) {
      const int cell = block.first_cell + local;
      touched.clear();
      for (int node : cell_corners(block, local))
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
