#include "tensormass/mesh/mesh_topology.hpp"

#include <algorithm>

#include "tensormass/kernels/registry.hpp"

namespace tensormass {

std::vector<std::vector<int>> cells_around_nodes(const Mesh& mesh) {
  std::vector<std::vector<int>> node_cells(mesh.node_count());
  for (const ElementBlock& block : mesh.blocks)
    for (int local = 0; local < block.count(); ++local)
      for (int node : block.cell_nodes(local)) node_cells[node].push_back(block.first_cell + local);
  return node_cells;
}

const tm_element_info* facet_element(int nodes) {
  for (const tm_element_info* element : Registry::instance().elements())
    if (element->dim == 2 && element->nodes == nodes) return element;
  return nullptr;
}

bool is_load_facet(int dim, int nodes) {
  return dim == 2 ? (nodes == 2 || nodes == 3) : facet_element(nodes) != nullptr;
}

int facet_corners(int dim, int nodes) {
  if (dim == 2) return 2;
  const tm_element_info* element = facet_element(nodes);
  return element ? element->corner_count : 0;
}

int facet_owner(const Mesh& mesh, const std::vector<std::vector<int>>& node_cells, std::span<const int> facet) {
  const int corners = facet_corners(mesh.dim, static_cast<int>(facet.size()));
  for (int cell : node_cells[facet[0]]) {
    const auto [block, local] = mesh.locate(cell);
    const auto nodes = mesh.blocks[block].cell_nodes(local);
    bool all = true;
    for (int c = 0; c < corners && all; ++c) all = std::find(nodes.begin(), nodes.end(), facet[c]) != nodes.end();
    if (all) return cell;
  }
  return -1;
}

}  // namespace tensormass
