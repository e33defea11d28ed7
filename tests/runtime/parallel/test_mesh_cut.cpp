// A mesh cut among ranks, each rank holding its part (mesh_cut.cpp), all
// simulated in one process: every part holds every node, its own cells and
// those touching its nodes, in the whole mesh's order, and its groups'
// cells among them; a model and assembler built on each part give the
// serial assembly's own rows bit for bit; node owners follow the lowest
// rank; parts pack and unpack exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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

TEST(MeshCut, PartsHoldEveryNodeAndTheCellsTheirRankAssembles) {
  const Mesh whole = mixed_beam();
  const int ranks = 3;
  const std::vector<int> owner = consecutive_parts(whole.cell_count(), ranks);
  const std::vector<int> node_owner = parallel::node_owners(whole, owner, ranks);
  std::vector<int> owned_by(whole.cell_count(), 0);
  for (int rank = 0; rank < ranks; ++rank) {
    SCOPED_TRACE(rank);
    const MeshPart part = parallel::cut_mesh(whole, owner, node_owner, rank);
    const Mesh& mesh = part.mesh;
    EXPECT_NO_THROW(mesh.validate());
    EXPECT_EQ(mesh.rest_positions, whole.rest_positions);
    EXPECT_EQ(part.cut.node_owner, node_owner);
    EXPECT_EQ(part.cut.whole_cell_count, whole.cell_count());
    ASSERT_EQ(static_cast<int>(part.cut.global_cell.size()), mesh.cell_count());
    EXPECT_TRUE(std::is_sorted(part.cut.global_cell.begin(), part.cut.global_cell.end()));
    std::vector<char> held(whole.cell_count(), 0);
    for (int cell = 0; cell < mesh.cell_count(); ++cell) {
      const int global = part.cut.global_cell[cell];
      held[global] = 1;
      EXPECT_EQ(whole_cell_nodes(mesh, cell), whole_cell_nodes(whole, global));
      EXPECT_EQ(part.cut.cell_owner[cell], owner[global]);
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
    ASSERT_EQ(mesh.groups.size(), whole.groups.size());
    for (std::size_t g = 0; g < whole.groups.size(); ++g) {
      EXPECT_EQ(mesh.groups[g].nodes, whole.groups[g].nodes);
      std::vector<int> kept;
      for (int cell : whole.groups[g].cells)
        if (held[cell]) kept.push_back(cell);
      std::vector<int> mapped;
      for (int cell : mesh.groups[g].cells) mapped.push_back(part.cut.global_cell[cell]);
      EXPECT_EQ(mapped, kept) << whole.groups[g].name;
      EXPECT_EQ(mesh.groups[g].facets.nodes, whole.groups[g].facets.nodes);
    }
  }
  EXPECT_TRUE(std::all_of(owned_by.begin(), owned_by.end(), [](int n) { return n == 1; }));
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
    for (int rank = 0; rank < ranks; ++rank) {
      MeshPart part = parallel::cut_mesh(whole, owner, node_owner, rank);
      const Model model(part.mesh, scene.model);
      ASSERT_EQ(model.free_dofs(), serial_model.free_dofs());
      const Distribution shared(model, std::move(part.cut), rank, ranks);
      EXPECT_TRUE(shared.holds_part());
      EXPECT_EQ(shared.assembled_cell_count(), model.cell_count());
      Assembler assembler(model, true, &shared);
      std::vector<double> g_rank(model.dof_count());
      assembler.assemble(u, g_rank, nullptr);  // one process: completing keeps own dofs only
      std::vector<double> mass = model.lumped_mass();
      shared.keep_own_dofs(mass);
      for (std::size_t i = 0; i < g.size(); ++i) g_sum[i] += g_rank[i], mass_sum[i] += mass[i];
      for (int cell = 0; cell < model.cell_count(); ++cell)
        if (shared.owns_cell(cell)) energy_scale += model.cell_energy_scale(cell);
    }
    for (std::size_t i = 0; i < g.size(); ++i) {
      ASSERT_EQ(g_sum[i], g[i]) << "dof " << i;
      ASSERT_EQ(mass_sum[i], serial_model.lumped_mass()[i]) << "dof " << i;
    }
    EXPECT_NEAR(energy_scale, serial_model.energy_scale(), 1e-14 * serial_model.energy_scale());
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
  for (int cell = 0; cell < model.cell_count(); ++cell) EXPECT_EQ(shared.local_cell(shared.global_cell(cell)), cell);
  int held = 0;
  for (int global = 0; global < whole.cell_count(); ++global) held += shared.local_cell(global) >= 0;
  EXPECT_EQ(held, model.cell_count());
  std::vector<double> values(model.cell_count());
  for (int cell = 0; cell < model.cell_count(); ++cell) values[cell] = 1.0 + shared.global_cell(cell);
  shared.share_cell_values(values);  // one process: other ranks' cells get nothing
  for (int cell = 0; cell < model.cell_count(); ++cell)
    EXPECT_EQ(values[cell], shared.owns_cell(cell) ? 1.0 + shared.global_cell(cell) : 0.0);
  CellCut short_cut = cut;
  short_cut.global_cell.pop_back();
  EXPECT_THROW(Distribution(model, short_cut, 1, 2), std::invalid_argument);
  CellCut unsorted = cut;
  std::swap(unsorted.global_cell[0], unsorted.global_cell[1]);
  EXPECT_THROW(Distribution(model, unsorted, 1, 2), std::invalid_argument);
  CellCut few_nodes = cut;
  few_nodes.node_owner.pop_back();
  EXPECT_THROW(Distribution(model, few_nodes, 1, 2), std::invalid_argument);
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
  EXPECT_EQ(back.cut.node_owner, part.cut.node_owner);
  EXPECT_EQ(back.cut.whole_cell_count, part.cut.whole_cell_count);
  EXPECT_THROW(parallel::unpack_mesh_part(std::vector<char>(bytes.begin(), bytes.end() - 1)), std::invalid_argument);
  EXPECT_THROW(parallel::unpack_mesh_part(parallel::pack_mesh(whole)), std::invalid_argument);
  EXPECT_THROW(parallel::unpack_mesh(bytes), std::invalid_argument);
}

}  // namespace
}  // namespace tensormass
