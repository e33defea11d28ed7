// A mesh cut among ranks, each rank holding its part (mesh_cut.cpp), all
// simulated in one process: every part holds its own cells and those
// touching its nodes, and the nodes they use, numbered in the part in the
// whole mesh's order, and its groups among them; a model and assembler
// built on each part give the
// serial assembly's own rows bit for bit; node owners follow the lowest
// rank; parts pack and unpack exactly; the ghost links of neighbouring
// parts match and a rank's own rows need only its own and ghost nodes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <stdexcept>

#include "support/cantilever.hpp"
#include "support/test_meshes.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/parallel/distribution.hpp"
#include "tensormass/parallel/mesh_broadcast.hpp"
#include "tensormass/parallel/mesh_cut.hpp"

namespace tensormass {
namespace {

Mesh mixed_beam() {
  BeamSpec spec;
  spec.dim = 3;
  spec.cells = {9, 2, 2};
  spec.size = {4.5, 1.0, 1.0};
  spec.phases = parse_beam_mix("hex8:0.34,tet6:0.33,prism6:0.33");
  return make_beam(spec);
}

std::vector<int> consecutive_parts(int cells, int parts) {
  std::vector<int> owner(cells);
  for (int cell = 0; cell < cells; ++cell) owner[cell] = cell * parts / cells;
  return owner;
}

std::vector<int> whole_cell_nodes(const Mesh& mesh, int cell) {
  const auto [b, local] = mesh.locate(cell);
  const auto nodes = mesh.blocks[b].cell_nodes(local);
  return {nodes.begin(), nodes.end()};
}

TEST(MeshCut, NodesBelongToTheLowestRankAmongTheirCells) {
  const Mesh mesh = mixed_beam();
  const std::vector<int> owner = consecutive_parts(mesh.cell_count(), 3);
  const std::vector<int> node_owner = parallel::node_owners(mesh, owner, 3);
  std::vector<int> lowest(mesh.node_count(), 3);
  for (int cell = 0; cell < mesh.cell_count(); ++cell)
    for (int node : whole_cell_nodes(mesh, cell)) lowest[node] = std::min(lowest[node], owner[cell]);
  EXPECT_EQ(node_owner, lowest);
  EXPECT_THROW(parallel::node_owners(mesh, std::vector<int>(3, 0), 3), std::invalid_argument);
  EXPECT_THROW(parallel::node_owners(mesh, std::vector<int>(mesh.cell_count(), 3), 3), std::invalid_argument);
}

/// A part's node numbers mapped to the whole mesh's.
std::vector<int> to_whole(const CellCut& cut, const std::vector<int>& nodes) {
  std::vector<int> whole;
  for (int node : nodes) whole.push_back(cut.global_node[node]);
  return whole;
}

/// The whole mesh's nodes rank `rank`'s part must hold: its own, those of
/// its cells (`held`: per whole cell) and of group facets touching its own.
std::vector<char> expected_nodes(const Mesh& whole, const std::vector<char>& held, const std::vector<int>& node_owner,
                                 int rank) {
  std::vector<char> needed(whole.node_count(), 0);
  for (int node = 0; node < whole.node_count(); ++node) needed[node] = node_owner[node] == rank;
  for (int cell = 0; cell < whole.cell_count(); ++cell)
    if (held[cell])
      for (int node : whole_cell_nodes(whole, cell)) needed[node] = 1;
  for (const Group& group : whole.groups)
    for (int f = 0; f < group.facets.count(); ++f) {
      const auto first = group.facets.nodes.begin() + group.facets.offsets[f];
      const auto last = group.facets.nodes.begin() + group.facets.offsets[f + 1];
      if (std::any_of(first, last, [&](int node) { return node_owner[node] == rank; }))
        for (auto node = first; node != last; ++node) needed[*node] = 1;
    }
  return needed;
}

TEST(MeshCut, PartsHoldTheirCellsAndTheNodesTheyUseNumberedInThePart) {
  const Mesh whole = mixed_beam();
  const int ranks = 3;
  const std::vector<int> owner = consecutive_parts(whole.cell_count(), ranks);
  const std::vector<int> node_owner = parallel::node_owners(whole, owner, ranks);
  std::vector<int> owned_by(whole.cell_count(), 0);
  int smaller_parts = 0;
  for (int rank = 0; rank < ranks; ++rank) {
    SCOPED_TRACE(rank);
    const MeshPart part = parallel::cut_mesh(whole, owner, node_owner, rank);
    const Mesh& mesh = part.mesh;
    const CellCut& cut = part.cut;
    EXPECT_NO_THROW(mesh.validate());
    EXPECT_EQ(cut.whole_cell_count, whole.cell_count());
    EXPECT_EQ(cut.whole_node_count, whole.node_count());
    ASSERT_EQ(static_cast<int>(cut.global_cell.size()), mesh.cell_count());
    ASSERT_EQ(static_cast<int>(cut.global_node.size()), mesh.node_count());
    ASSERT_EQ(static_cast<int>(cut.node_owner.size()), mesh.node_count());
    EXPECT_TRUE(std::is_sorted(cut.global_cell.begin(), cut.global_cell.end()));
    EXPECT_TRUE(std::adjacent_find(cut.global_node.begin(), cut.global_node.end(), std::greater_equal<>()) ==
                cut.global_node.end());
    smaller_parts += mesh.node_count() < whole.node_count();
    for (int node = 0; node < mesh.node_count(); ++node) {
      const int global = cut.global_node[node];
      ASSERT_EQ(cut.node_owner[node], node_owner[global]);
      for (int k = 0; k < 3; ++k) ASSERT_EQ(mesh.rest_positions[3 * node + k], whole.rest_positions[3 * global + k]);
    }
    std::vector<char> held(whole.cell_count(), 0);
    for (int cell = 0; cell < mesh.cell_count(); ++cell) {
      const int global = cut.global_cell[cell];
      held[global] = 1;
      EXPECT_EQ(to_whole(cut, whole_cell_nodes(mesh, cell)), whole_cell_nodes(whole, global));
      EXPECT_EQ(cut.cell_owner[cell], owner[global]);
      owned_by[global] += owner[global] == rank;
      const auto [b, local] = mesh.locate(cell);
      const auto [whole_b, whole_local] = whole.locate(global);
      EXPECT_EQ(mesh.blocks[b].source_ids[local], whole.blocks[whole_b].source_ids[whole_local]);
    }
    for (int cell = 0; cell < whole.cell_count(); ++cell) {  // held: own, or touching an own node
      const auto nodes = whole_cell_nodes(whole, cell);
      const bool touches = std::any_of(nodes.begin(), nodes.end(), [&](int n) { return node_owner[n] == rank; });
      EXPECT_EQ(held[cell] != 0, owner[cell] == rank || touches) << "cell " << cell;
    }
    const std::vector<char> needed = expected_nodes(whole, held, node_owner, rank);
    std::vector<int> expected;
    for (int node = 0; node < whole.node_count(); ++node)
      if (needed[node]) expected.push_back(node);
    EXPECT_EQ(cut.global_node, expected);
    ASSERT_EQ(mesh.groups.size(), whole.groups.size());
    for (std::size_t g = 0; g < whole.groups.size(); ++g) {
      SCOPED_TRACE(whole.groups[g].name);
      std::vector<int> kept_nodes, kept_cells, mapped_cells;
      for (int node : whole.groups[g].nodes)
        if (needed[node]) kept_nodes.push_back(node);
      EXPECT_EQ(to_whole(cut, mesh.groups[g].nodes), kept_nodes);
      for (int cell : whole.groups[g].cells)
        if (held[cell]) kept_cells.push_back(cell);
      for (int cell : mesh.groups[g].cells) mapped_cells.push_back(cut.global_cell[cell]);
      EXPECT_EQ(mapped_cells, kept_cells);
      const FacetSet& facets = whole.groups[g].facets;
      std::vector<int> kept_facet_nodes;
      for (int f = 0; f < facets.count(); ++f) {
        const auto first = facets.nodes.begin() + facets.offsets[f],
                   last = facets.nodes.begin() + facets.offsets[f + 1];
        if (std::all_of(first, last, [&](int node) { return needed[node] != 0; }))
          kept_facet_nodes.insert(kept_facet_nodes.end(), first, last);
      }
      EXPECT_EQ(to_whole(cut, mesh.groups[g].facets.nodes), kept_facet_nodes);
      EXPECT_EQ(mesh.groups[g].facets.count() + 1, static_cast<int>(mesh.groups[g].facets.offsets.size()));
    }
  }
  EXPECT_TRUE(std::all_of(owned_by.begin(), owned_by.end(), [](int n) { return n == 1; }));
  EXPECT_GT(smaller_parts, 0);
}

TEST(MeshCut, PartsNameTheirCellsByTheWholeMeshsNumbers) {
  const Mesh whole = mixed_beam();
  const std::vector<int> owner = consecutive_parts(whole.cell_count(), 2);
  MeshPart part = parallel::cut_mesh(whole, owner, parallel::node_owners(whole, owner, 2), 1);
  EXPECT_EQ(part.mesh.cell_numbers, part.cut.global_cell);
  for (int cell = 0; cell < part.mesh.cell_count(); ++cell)
    ASSERT_EQ(part.mesh.describe_cell(cell), whole.describe_cell(part.cut.global_cell[cell]));
  part.mesh.cell_numbers.pop_back();
  EXPECT_THROW(part.mesh.validate(), InputError);
}

TEST(MeshCut, ModelsOnThePartsAssembleTheSerialOwnRows) {
  const Mesh whole = mixed_beam();
  const Scene scene = test::cantilever("neohookean");
  const Model serial_model(whole, scene.model);
  std::vector<double> u(serial_model.dof_count());
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = 0.01 * std::sin(0.37 * i + 0.2);
  serial_model.apply_constraints(1.0, u);
  Assembler serial(serial_model);
  std::vector<double> g(serial_model.dof_count());
  serial.assemble(u, g, nullptr);
  for (int ranks : {2, 3}) {
    SCOPED_TRACE(ranks);
    const std::vector<int> owner = consecutive_parts(whole.cell_count(), ranks);
    const std::vector<int> node_owner = parallel::node_owners(whole, owner, ranks);
    std::vector<double> g_sum(g.size(), 0.0), mass_sum(g.size(), 0.0);
    double energy_scale = 0.0;
    int own_free = 0;
    const int d = serial_model.dim();
    for (int rank = 0; rank < ranks; ++rank) {
      MeshPart part = parallel::cut_mesh(whole, owner, node_owner, rank);
      const Model model(part.mesh, scene.model);
      const Distribution shared(model, std::move(part.cut), rank, ranks);
      EXPECT_TRUE(shared.holds_part());
      EXPECT_EQ(shared.assembled_cell_count(), model.cell_count());
      for (int node = 0; node < model.mesh().node_count(); ++node)  // the same constraints as the whole mesh's
        for (int a = 0; a < d; ++a)
          ASSERT_EQ(model.free_index()[d * node + a] >= 0,
                    serial_model.free_index()[d * shared.global_node(node) + a] >= 0);
      own_free += static_cast<int>(shared.owned_free_rows().size());
      Assembler assembler(model, true, &shared);
      const std::vector<double> u_rank = shared.local_dofs(u);
      std::vector<double> g_rank(model.dof_count());
      assembler.assemble(u_rank, g_rank, nullptr);  // own rows; ghost rows zeroed
      std::vector<double> mass = model.lumped_mass();
      shared.keep_own_dofs(mass);
      for (int node = 0; node < model.mesh().node_count(); ++node)
        for (int a = 0; a < d; ++a) {
          const std::size_t whole_dof = d * shared.global_node(node) + a;
          g_sum[whole_dof] += g_rank[d * node + a], mass_sum[whole_dof] += mass[d * node + a];
        }
      for (int cell = 0; cell < model.cell_count(); ++cell)
        if (shared.owns_cell(cell)) energy_scale += model.cell_energy_scale(cell);
    }
    for (std::size_t i = 0; i < g.size(); ++i) {
      ASSERT_EQ(g_sum[i], g[i]) << "dof " << i;
      ASSERT_EQ(mass_sum[i], serial_model.lumped_mass()[i]) << "dof " << i;
    }
    EXPECT_NEAR(energy_scale, serial_model.energy_scale(), 1e-14 * serial_model.energy_scale());
    EXPECT_EQ(own_free, serial_model.free_dof_count());
  }
}

TEST(MeshCut, DistributionMapsCellsAndRefusesCutsThatDoNotFit) {
  const Mesh whole = mixed_beam();
  const Scene scene = test::cantilever("neohookean");
  const std::vector<int> owner = consecutive_parts(whole.cell_count(), 2);
  const std::vector<int> node_owner = parallel::node_owners(whole, owner, 2);
  MeshPart part = parallel::cut_mesh(whole, owner, node_owner, 1);
  const Model model(part.mesh, scene.model);
  const CellCut cut = part.cut;
  const Distribution shared(model, cut, 1, 2);
  EXPECT_EQ(shared.whole_cell_count(), whole.cell_count());
  EXPECT_EQ(shared.whole_node_count(), whole.node_count());
  for (int cell = 0; cell < model.cell_count(); ++cell) EXPECT_EQ(shared.local_cell(shared.global_cell(cell)), cell);
  const int d = model.dim();
  std::vector<double> whole_dofs(static_cast<std::size_t>(d) * whole.node_count());
  for (std::size_t dof = 0; dof < whole_dofs.size(); ++dof) whole_dofs[dof] = static_cast<double>(dof);
  const std::vector<double> local = shared.local_dofs(whole_dofs);
  ASSERT_EQ(static_cast<int>(local.size()), model.dof_count());
  for (int node = 0; node < model.mesh().node_count(); ++node)
    for (int a = 0; a < d; ++a) ASSERT_EQ(local[d * node + a], d * cut.global_node[node] + a);
  EXPECT_THROW(shared.local_dofs(local), std::invalid_argument);
  int held = 0;
  for (int global = 0; global < whole.cell_count(); ++global) held += shared.local_cell(global) >= 0;
  EXPECT_EQ(held, model.cell_count());
  CellCut short_cut = cut;
  short_cut.global_cell.pop_back();
  EXPECT_THROW(Distribution(model, short_cut, 1, 2), std::invalid_argument);
  CellCut unsorted = cut;
  std::swap(unsorted.global_cell[0], unsorted.global_cell[1]);
  EXPECT_THROW(Distribution(model, unsorted, 1, 2), std::invalid_argument);
  CellCut few_nodes = cut;
  few_nodes.node_owner.pop_back();
  EXPECT_THROW(Distribution(model, few_nodes, 1, 2), std::invalid_argument);
  CellCut unsorted_nodes = cut;
  std::swap(unsorted_nodes.global_node[0], unsorted_nodes.global_node[1]);
  EXPECT_THROW(Distribution(model, unsorted_nodes, 1, 2), std::invalid_argument);
  CellCut outside = cut;
  outside.whole_node_count = outside.global_node.back();
  EXPECT_THROW(Distribution(model, outside, 1, 2), std::invalid_argument);
}

TEST(MeshCut, PartsPackAndUnpackExactly) {
  const Mesh whole = read_mesh(meshtest::data_dir() + "hybrid_o1.msh41b.msh");
  const std::vector<int> owner = consecutive_parts(whole.cell_count(), 2);
  const MeshPart part = parallel::cut_mesh(whole, owner, parallel::node_owners(whole, owner, 2), 1);
  const std::vector<char> bytes = parallel::pack_mesh_part(part);
  const MeshPart back = parallel::unpack_mesh_part(bytes);
  meshtest::expect_identical(part.mesh, back.mesh, true);
  EXPECT_EQ(back.cut.global_cell, part.cut.global_cell);
  EXPECT_EQ(back.cut.cell_owner, part.cut.cell_owner);
  EXPECT_EQ(back.cut.global_node, part.cut.global_node);
  EXPECT_EQ(back.cut.node_owner, part.cut.node_owner);
  EXPECT_EQ(back.cut.whole_cell_count, part.cut.whole_cell_count);
  EXPECT_EQ(back.cut.whole_node_count, part.cut.whole_node_count);
  EXPECT_THROW(parallel::unpack_mesh_part(std::vector<char>(bytes.begin(), bytes.end() - 1)), std::invalid_argument);
  EXPECT_THROW(parallel::unpack_mesh_part(parallel::pack_mesh(whole)), std::invalid_argument);
  EXPECT_THROW(parallel::unpack_mesh(bytes), std::invalid_argument);
}

/// The parts of a 3-rank cut and the Distribution each rank builds on its part.
struct PartsOfThree {
  static constexpr int ranks = 3;
  Mesh whole = mixed_beam();
  Scene scene = test::cantilever("neohookean");
  std::vector<int> owner = consecutive_parts(whole.cell_count(), ranks);
  std::vector<int> node_owner = parallel::node_owners(whole, owner, ranks);
  std::vector<MeshPart> parts;
  std::vector<Model> models;
  std::vector<Distribution> shared;
  PartsOfThree() {
    parts.reserve(ranks), models.reserve(ranks), shared.reserve(ranks);
    for (int rank = 0; rank < ranks; ++rank) {
      parts.push_back(parallel::cut_mesh(whole, owner, node_owner, rank));
      models.emplace_back(parts.back().mesh, scene.model);
      shared.emplace_back(models.back(), parts.back().cut, rank, ranks);
    }
  }
  /// The index of `rank` among shared[of]'s neighbours, or -1.
  int link(int of, int rank) const {
    const auto& n = shared[of].neighbours();
    const auto it = std::find(n.begin(), n.end(), rank);
    return it == n.end() ? -1 : static_cast<int>(it - n.begin());
  }
};

TEST(MeshCut, GhostLinksOfNeighboursMatchAndCoverEveryNodeAndCellOfAPart) {
  const PartsOfThree cut;
  for (int rank = 0; rank < cut.ranks; ++rank) {
    SCOPED_TRACE(rank);
    const Distribution& shared = cut.shared[rank];
    const CellCut& part_cut = cut.parts[rank].cut;
    ASSERT_TRUE(shared.divides_state());
    std::vector<int> own;
    for (int node = 0; node < cut.whole.node_count(); ++node)
      if (cut.node_owner[node] == rank) own.push_back(node);
    EXPECT_EQ(to_whole(part_cut, shared.own_nodes()), own);
    std::vector<int> needed;  // every node of the part's cells, in the part's numbers
    const Mesh& mesh = cut.parts[rank].mesh;
    for (int cell = 0; cell < mesh.cell_count(); ++cell)
      for (int node : whole_cell_nodes(mesh, cell)) needed.push_back(node);
    std::sort(needed.begin(), needed.end());
    needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
    std::vector<int> ghosts;
    std::copy_if(needed.begin(), needed.end(), std::back_inserter(ghosts),
                 [&](int node) { return !shared.owns_node(node); });
    EXPECT_EQ(shared.ghost_nodes(), ghosts);
    EXPECT_FALSE(ghosts.empty());
    EXPECT_FALSE(shared.neighbours().empty());
    std::vector<int> received, received_cells;
    for (std::size_t i = 0; i < shared.neighbours().size(); ++i) {
      const int other = shared.neighbours()[i];
      ASSERT_NE(other, rank);
      const int back = cut.link(other, rank);
      ASSERT_GE(back, 0) << "rank " << other << " does not link back";
      const CellCut& other_cut = cut.parts[other].cut;
      EXPECT_EQ(to_whole(part_cut, shared.sent_nodes(i)), to_whole(other_cut, cut.shared[other].received_nodes(back)));
      EXPECT_EQ(to_whole(part_cut, shared.received_nodes(i)), to_whole(other_cut, cut.shared[other].sent_nodes(back)));
      const auto cells_to_whole = [](const Distribution& of, const std::vector<int>& cells) {
        std::vector<int> whole;
        for (int cell : cells) whole.push_back(of.global_cell(cell));
        return whole;
      };
      EXPECT_EQ(cells_to_whole(shared, shared.sent_cells(i)),
                cells_to_whole(cut.shared[other], cut.shared[other].received_cells(back)));
      EXPECT_EQ(cells_to_whole(shared, shared.received_cells(i)),
                cells_to_whole(cut.shared[other], cut.shared[other].sent_cells(back)));
      for (int cell : shared.received_cells(i)) EXPECT_EQ(shared.cell_owner(cell), other);
      for (int cell : shared.sent_cells(i)) EXPECT_TRUE(shared.owns_cell(cell));
      received_cells.insert(received_cells.end(), shared.received_cells(i).begin(), shared.received_cells(i).end());
      for (int node : shared.received_nodes(i)) EXPECT_EQ(shared.node_owner(node), other);
      for (int node : shared.sent_nodes(i)) EXPECT_TRUE(shared.owns_node(node));
      received.insert(received.end(), shared.received_nodes(i).begin(), shared.received_nodes(i).end());
    }
    std::sort(received.begin(), received.end());
    EXPECT_EQ(received, ghosts);  // each ghost comes once, from its owner
    std::sort(received_cells.begin(), received_cells.end());
    std::vector<int> foreign_cells;  // each held cell another rank owns comes once, from its owner
    for (int cell = 0; cell < mesh.cell_count(); ++cell)
      if (!shared.owns_cell(cell)) foreign_cells.push_back(cell);
    EXPECT_EQ(received_cells, foreign_cells);
  }
}

TEST(MeshCut, OwnRowsNeedOnlyOwnAndGhostNodes) {
  const PartsOfThree cut;
  const Model serial_model(cut.whole, cut.scene.model);
  std::vector<double> u(serial_model.dof_count());
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = 0.01 * std::sin(0.37 * i + 0.2);
  serial_model.apply_constraints(1.0, u);
  std::vector<double> g(u.size());
  Assembler(serial_model).assemble(u, g, nullptr);
  const int dim = serial_model.dim();
  for (int rank = 0; rank < cut.ranks; ++rank) {
    SCOPED_TRACE(rank);
    const Distribution& shared = cut.shared[rank];
    const Model& model = cut.models[rank];
    std::vector<double> u_rank(model.dof_count(), std::nan(""));  // nodes this rank must not read
    for (const auto* nodes : {&shared.own_nodes(), &shared.ghost_nodes()})
      for (int node : *nodes)
        for (int k = 0; k < dim; ++k) u_rank[node * dim + k] = u[shared.global_node(node) * dim + k];
    Assembler assembler(model, true, &shared);
    std::vector<double> g_rank(u_rank.size());
    assembler.assemble(u_rank, g_rank, nullptr);
    for (int node : shared.own_nodes())
      for (int k = 0; k < dim; ++k)
        ASSERT_EQ(g_rank[node * dim + k], g[shared.global_node(node) * dim + k]) << "node " << node;
  }
}

}  // namespace
}  // namespace tensormass
