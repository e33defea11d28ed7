#include "tensormass/parallel/mesh_cut.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace tensormass::parallel {

std::vector<int> node_owners(const Mesh& mesh, std::span<const int> cell_owner, int ranks) {
  if (static_cast<int>(cell_owner.size()) != mesh.cell_count())
    throw std::invalid_argument("node_owners: " + std::to_string(cell_owner.size()) + " cell owners for " +
                                std::to_string(mesh.cell_count()) + " cells");
  std::vector<int> owner(static_cast<std::size_t>(mesh.node_count()), ranks);
  for (const ElementBlock& block : mesh.blocks)
    for (int local = 0; local < block.count(); ++local) {
      const int rank = cell_owner[static_cast<std::size_t>(block.first_cell + local)];
      if (rank < 0 || rank >= ranks)
        throw std::invalid_argument("node_owners: cell " + std::to_string(block.first_cell + local) +
                                    " owned by rank " + std::to_string(rank));
      for (int node : block.cell_nodes(local)) owner[node] = std::min(owner[node], rank);
    }
  for (int& rank : owner)
    if (rank == ranks) rank = 0;  // a node in no cell: no rows to speak of, give it to rank 0
  return owner;
}

MeshPart cut_mesh(const Mesh& whole, std::span<const int> cell_owner, std::span<const int> node_owner, int rank) {
  MeshPart part;
  Mesh& mesh = part.mesh;
  mesh.dim = whole.dim;
  mesh.source = whole.source;
  mesh.rest_positions = whole.rest_positions;
  mesh.node_source_ids = whole.node_source_ids;
  // Per cell of the whole mesh: its index in the part, or -1.
  std::vector<int> local_of(static_cast<std::size_t>(whole.cell_count()), -1);
  int count = 0;
  for (const ElementBlock& block : whole.blocks) {
    ElementBlock kept;
    kept.element = block.element;
    kept.first_cell = count;
    for (int local = 0; local < block.count(); ++local) {
      const int cell = block.first_cell + local;
      const auto nodes = block.cell_nodes(local);
      const bool held = cell_owner[static_cast<std::size_t>(cell)] == rank ||
                        std::any_of(nodes.begin(), nodes.end(), [&](int node) { return node_owner[node] == rank; });
      if (!held) continue;
      local_of[static_cast<std::size_t>(cell)] = count++;
      kept.connectivity.insert(kept.connectivity.end(), nodes.begin(), nodes.end());
      kept.source_ids.push_back(block.source_ids[static_cast<std::size_t>(local)]);
      part.cut.global_cell.push_back(cell);
      part.cut.cell_owner.push_back(cell_owner[static_cast<std::size_t>(cell)]);
    }
    if (kept.count() > 0) mesh.blocks.push_back(std::move(kept));
  }
  for (const Group& group : whole.groups) {
    Group kept{group.name, group.dim, group.nodes, {}, group.facets};
    for (int cell : group.cells)
      if (const int local = local_of[static_cast<std::size_t>(cell)]; local >= 0) kept.cells.push_back(local);
    mesh.groups.push_back(std::move(kept));
  }
  mesh.cell_numbers = part.cut.global_cell;
  part.cut.node_owner.assign(node_owner.begin(), node_owner.end());
  part.cut.whole_cell_count = whole.cell_count();
  return part;
}

}  // namespace tensormass::parallel
