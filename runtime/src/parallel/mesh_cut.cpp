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

namespace {

/// The part's cells, in the whole mesh's order, with whole-mesh node numbers.
std::vector<ElementBlock> held_blocks(const Mesh& whole, std::span<const int> cell_owner,
                                      std::span<const int> node_owner, int rank, CellCut& cut) {
  std::vector<ElementBlock> blocks;
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
      ++count;
      kept.connectivity.insert(kept.connectivity.end(), nodes.begin(), nodes.end());
      kept.source_ids.push_back(block.source_ids[static_cast<std::size_t>(local)]);
      cut.global_cell.push_back(cell);
      cut.cell_owner.push_back(cell_owner[static_cast<std::size_t>(cell)]);
    }
    if (kept.count() > 0) blocks.push_back(std::move(kept));
  }
  return blocks;
}

/// Per node of the whole mesh: whether the part holds it.
std::vector<char> held_nodes(const Mesh& whole, const std::vector<ElementBlock>& blocks,
                             std::span<const int> node_owner, int rank) {
  std::vector<char> held(static_cast<std::size_t>(whole.node_count()), 0);
  for (std::size_t node = 0; node < held.size(); ++node) held[node] = node_owner[node] == rank;
  for (const ElementBlock& block : blocks)
    for (int node : block.connectivity) held[static_cast<std::size_t>(node)] = 1;
  // A facet touching an own node loads that node's row: all its nodes come too.
  for (const Group& group : whole.groups)
    for (int f = 0; f < group.facets.count(); ++f) {
      const auto first = group.facets.nodes.begin() + group.facets.offsets[f];
      const auto last = group.facets.nodes.begin() + group.facets.offsets[f + 1];
      if (std::any_of(first, last, [&](int node) { return node_owner[node] == rank; }))
        for (auto node = first; node != last; ++node) held[static_cast<std::size_t>(*node)] = 1;
    }
  return held;
}

/// A group's facets whose nodes are all held, renumbered.
FacetSet held_facets(const FacetSet& facets, const std::vector<int>& local_node) {
  FacetSet kept;
  for (int f = 0; f < facets.count(); ++f) {
    const auto first = facets.nodes.begin() + facets.offsets[f];
    const auto last = facets.nodes.begin() + facets.offsets[f + 1];
    if (std::any_of(first, last, [&](int node) { return local_node[node] < 0; })) continue;
    for (auto node = first; node != last; ++node) kept.nodes.push_back(local_node[*node]);
    kept.offsets.push_back(static_cast<int>(kept.nodes.size()));
    kept.orders.push_back(facets.orders[f]);
  }
  return kept;
}

}  // namespace

MeshPart cut_mesh(const Mesh& whole, std::span<const int> cell_owner, std::span<const int> node_owner, int rank) {
  MeshPart part;
  CellCut& cut = part.cut;
  Mesh& mesh = part.mesh;
  mesh.dim = whole.dim;
  mesh.source = whole.source;
  mesh.blocks = held_blocks(whole, cell_owner, node_owner, rank, cut);
  const std::vector<char> held = held_nodes(whole, mesh.blocks, node_owner, rank);
  std::vector<int> local_node(held.size(), -1);
  for (std::size_t node = 0; node < held.size(); ++node) {
    if (!held[node]) continue;
    local_node[node] = static_cast<int>(cut.global_node.size());
    cut.global_node.push_back(static_cast<int>(node));
    cut.node_owner.push_back(node_owner[node]);
    mesh.rest_positions.insert(mesh.rest_positions.end(), whole.rest_positions.begin() + 3 * node,
                               whole.rest_positions.begin() + 3 * node + 3);
    if (!whole.node_source_ids.empty()) mesh.node_source_ids.push_back(whole.node_source_ids[node]);
  }
  for (ElementBlock& block : mesh.blocks)
    for (int& node : block.connectivity) node = local_node[static_cast<std::size_t>(node)];
  std::vector<int> local_cell(static_cast<std::size_t>(whole.cell_count()), -1);
  for (std::size_t cell = 0; cell < cut.global_cell.size(); ++cell)
    local_cell[static_cast<std::size_t>(cut.global_cell[cell])] = static_cast<int>(cell);
  for (const Group& group : whole.groups) {
    Group kept{group.name, group.dim, {}, {}, held_facets(group.facets, local_node)};
    for (int node : group.nodes)
      if (local_node[node] >= 0) kept.nodes.push_back(local_node[node]);
    for (int cell : group.cells)
      if (const int local = local_cell[static_cast<std::size_t>(cell)]; local >= 0) kept.cells.push_back(local);
    mesh.groups.push_back(std::move(kept));
  }
  mesh.cell_numbers = cut.global_cell;
  cut.whole_cell_count = whole.cell_count();
  cut.whole_node_count = whole.node_count();
  return part;
}

}  // namespace tensormass::parallel
