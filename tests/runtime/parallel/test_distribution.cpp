// Distribution and the assembler over MPI ranks, simulated in one process:
// each rank's own rows of the forces and the tangent equal the serial
// assembly bit for bit, the ranks' own rows cover every dof once, the
// energies add up, and the rank-by-rank numbering is a permutation with one
// contiguous range per rank. Also the cell graph and the Scotch cut.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "support/cantilever.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/parallel/cell_partition.hpp"
#include "tensormass/parallel/distribution.hpp"

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

/// Cells cut into `parts` runs of consecutive cells (the partitioner's
/// stand-in where the test must not depend on PETSc).
std::vector<int> consecutive_parts(int cells, int parts) {
  std::vector<int> owner(cells);
  for (int cell = 0; cell < cells; ++cell) owner[cell] = cell * parts / cells;
  return owner;
}

/// A displacement that bends and stretches every cell a little.
std::vector<double> some_displacement(const Model& model) {
  std::vector<double> u(model.dof_count());
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = 0.01 * std::sin(0.37 * i + 0.2);
  model.apply_constraints(1.0, u);
  return u;
}

struct MixedBeam {
  Mesh mesh = mixed_beam();
  Scene scene = test::cantilever("neohookean");
  Model model{mesh, scene.model};
};

/// The rank's own rows of K_rank equal the serial K's bit for bit (same
/// columns), and its other rows are empty: each rank holds its rows of the
/// tangent only. Counts the own rows in row_seen.
void expect_own_rows_equal(const Distribution& shared, const SparseMatrix& K_rank, const SparseMatrix& K,
                           std::vector<int>& row_seen) {
  std::vector<char> own(K.rows, 0);
  for (int row : shared.owned_free_rows()) {
    own[row] = 1;
    ++row_seen[row];
    const int length = K.row_start[row + 1] - K.row_start[row];
    ASSERT_EQ(K_rank.row_start[row + 1] - K_rank.row_start[row], length) << "row " << row;
    for (int k = 0; k < length; ++k) {
      ASSERT_EQ(K_rank.columns[K_rank.row_start[row] + k], K.columns[K.row_start[row] + k]) << "row " << row;
      ASSERT_EQ(K_rank.values[K_rank.row_start[row] + k], K.values[K.row_start[row] + k])
          << "rank " << shared.rank() << " of " << shared.size() << ", row " << row;
    }
  }
  for (int row = 0; row < K.rows; ++row) {
    if (!own[row]) {
      ASSERT_EQ(K_rank.row_start[row + 1], K_rank.row_start[row]) << "row " << row << " not empty";
    }
  }
  if (shared.size() > 1) {
    EXPECT_LT(K_rank.nonzeros(), K.nonzeros());
  }
}

TEST(Distribution, OwnRowsOfEachRankEqualTheSerialAssembly) {
  MixedBeam s;
  const Model& model = s.model;
  const std::vector<double> u = some_displacement(model);
  Assembler serial(model);
  SparseMatrix K = serial.pattern();
  std::vector<double> g(model.dof_count());
  serial.assemble(u, g, &K);
  const double energy = serial.energy(u);
  for (int ranks : {1, 2, 3}) {
    const std::vector<int> owner = consecutive_parts(model.cell_count(), ranks);
    std::vector<double> g_sum(model.dof_count(), 0.0);
    std::vector<int> row_seen(K.rows, 0);
    double energy_sum = 0.0;
    for (int rank = 0; rank < ranks; ++rank) {
      const Distribution shared(model, owner, rank, ranks);
      Assembler assembler(model);
      assembler.distribute(&shared);
      SparseMatrix K_rank = assembler.pattern();
      std::vector<double> g_rank(model.dof_count());
      assembler.assemble(u, g_rank, &K_rank);  // one process: completing keeps own dofs only
      for (std::size_t i = 0; i < g.size(); ++i) g_sum[i] += g_rank[i];
      expect_own_rows_equal(shared, K_rank, K, row_seen);
      energy_sum += assembler.energy(u);
      EXPECT_LE(shared.assembled_cell_count(), model.cell_count());
    }
    for (std::size_t i = 0; i < g.size(); ++i) ASSERT_EQ(g_sum[i], g[i]) << "dof " << i << ", " << ranks << " ranks";
    EXPECT_TRUE(std::all_of(row_seen.begin(), row_seen.end(), [](int seen) { return seen == 1; }));
    EXPECT_NEAR(energy_sum, energy, 1e-12 * std::abs(energy));
  }
}

TEST(Distribution, FoldedLinearCellsAreCountedOnceToo) {
  MixedBeam s;
  s.scene.model.materials[0].law = "hooke";
  Model model(s.mesh, s.scene.model);
  const std::vector<double> u = some_displacement(model);
  Assembler serial(model);
  std::vector<double> g(model.dof_count());
  SparseMatrix K = serial.pattern();
  serial.assemble(u, g, &K);
  ASSERT_EQ(serial.folded_cell_count(), model.cell_count());
  const std::vector<int> owner = consecutive_parts(model.cell_count(), 2);
  std::vector<double> g_sum(model.dof_count(), 0.0);
  std::vector<int> row_seen(K.rows, 0);
  double energy_sum = 0.0;
  for (int rank = 0; rank < 2; ++rank) {
    const Distribution shared(model, owner, rank, 2);
    Assembler assembler(model);
    std::vector<double> g_rank(model.dof_count());
    assembler.assemble(u, g_rank, nullptr);  // folds before the distribution: its map follows the new pattern
    assembler.distribute(&shared);
    SparseMatrix K_rank = assembler.pattern();
    assembler.assemble(u, g_rank, &K_rank);
    expect_own_rows_equal(shared, K_rank, K, row_seen);
    for (std::size_t i = 0; i < g.size(); ++i) g_sum[i] += g_rank[i];
    energy_sum += assembler.energy(u);
  }
  for (std::size_t i = 0; i < g.size(); ++i) ASSERT_EQ(g_sum[i], g[i]) << "dof " << i;
  EXPECT_NEAR(energy_sum, serial.energy(u), 1e-12 * std::abs(serial.energy(u)));
}

TEST(Distribution, NumbersRowsRankByRankInContiguousRanges) {
  MixedBeam s;
  const Model& model = s.model;
  const int ranks = 3;
  const std::vector<int> owner = consecutive_parts(model.cell_count(), ranks);
  std::vector<int> all_rows;
  int next_first = 0;
  for (int rank = 0; rank < ranks; ++rank) {
    const Distribution shared(model, owner, rank, ranks);
    EXPECT_EQ(shared.first_global_row(), next_first);
    const auto& own = shared.owned_free_rows();
    EXPECT_TRUE(std::is_sorted(own.begin(), own.end()));
    for (std::size_t i = 0; i < own.size(); ++i) EXPECT_EQ(shared.global_row()[own[i]], next_first + int(i));
    next_first += static_cast<int>(own.size());
    all_rows.insert(all_rows.end(), shared.global_row().begin(), shared.global_row().end());
    // A node belongs to the lowest rank among its cells' owners.
    for (int cell = 0; cell < model.cell_count(); ++cell)
      for (int node : model.cell_nodes(cell)) EXPECT_LE(shared.node_owner(node), owner[cell]);
  }
  EXPECT_EQ(next_first, model.free_dof_count());
  std::vector<int> one_numbering(all_rows.begin(), all_rows.begin() + model.free_dof_count());
  std::sort(one_numbering.begin(), one_numbering.end());
  for (int i = 0; i < model.free_dof_count(); ++i) ASSERT_EQ(one_numbering[i], i);
}

TEST(Distribution, RefusesWrongOwnersAndRanks) {
  MixedBeam s;
  EXPECT_THROW(Distribution(s.model, std::vector<int>(3, 0), 0, 1), std::invalid_argument);
  EXPECT_THROW(Distribution(s.model, std::vector<int>(s.model.cell_count(), 2), 0, 2), std::invalid_argument);
  EXPECT_THROW(Distribution(s.model, std::vector<int>(s.model.cell_count(), 0), 2, 2), std::invalid_argument);
}

TEST(Distribution, SolversOtherThanPetscRefuseToBeShared) {
  MixedBeam s;
  const Distribution shared(s.model, std::vector<int>(s.model.cell_count(), 0), 0, 1);
  LinearSolverSettings settings;
  for (LinearSolverType type : {LinearSolverType::cholmod, LinearSolverType::cg}) {
    settings.type = type;
    try {
      make_linear_solver(settings)->distribute(shared);
      ADD_FAILURE() << "no error";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find("solver.backend: petsc"), std::string::npos) << error.what();
    }
  }
}

TEST(CellGraph, CellsSharingAFaceAreNeighbours) {
  // 2 x 1 x 1 hexes: each cube in 6 tets (Kuhn): every tet has at least one
  // face neighbour, none lists itself, and the graph is symmetric.
  const Mesh mesh = test::beam(3, "tet6", {2, 1, 1});
  const Scene scene = test::cantilever("hooke");
  const Model model(mesh, scene.model);
  const parallel::CellGraph graph = parallel::make_cell_graph(model.mesh());
  ASSERT_EQ(static_cast<int>(graph.row_start.size()), model.cell_count() + 1);
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const auto begin = graph.columns.begin() + graph.row_start[cell],
               end = graph.columns.begin() + graph.row_start[cell + 1];
    EXPECT_GT(end - begin, 0) << "cell " << cell;
    EXPECT_EQ(std::find(begin, end, cell), end);
    for (auto it = begin; it != end; ++it) {
      const auto other_begin = graph.columns.begin() + graph.row_start[*it];
      const auto other_end = graph.columns.begin() + graph.row_start[*it + 1];
      EXPECT_NE(std::find(other_begin, other_end, cell), other_end) << cell << " - " << *it;
    }
  }
}

TEST(CellPartition, CutsIntoBalancedNonEmptyParts) {
  if (!petsc_available()) GTEST_SKIP() << "this build has no PETSc and Scotch";
  const Mesh mesh = test::beam(3, "tet6", {12, 3, 3});
  const Scene scene = test::cantilever("hooke");
  const Model model(mesh, scene.model);
  for (int parts : {1, 2, 3}) {
    const std::vector<int> owner = parallel::partition_cells(model.mesh(), parts);
    std::vector<int> count(parts, 0);
    for (int p : owner) {
      ASSERT_GE(p, 0);
      ASSERT_LT(p, parts);
      ++count[p];
    }
    for (int p = 0; p < parts; ++p)
      EXPECT_NEAR(count[p], double(model.cell_count()) / parts, 0.1 * model.cell_count() / parts) << parts;
    EXPECT_EQ(parallel::partition_cells(model.mesh(), parts), owner) << "the cut repeats";
  }
  EXPECT_THROW(parallel::partition_cells(model.mesh(), model.cell_count() + 1), InputError);
}

}  // namespace
}  // namespace tensormass
