// Assembly: the sparse tangent is the derivative of the assembled forces,
// and results do not depend on the number of threads.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "support/assembly_checks.hpp"
#include "support/cantilever.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

using test::entry;
using test::wavy_displacement;

/// A 3D beam of `cells` unit-long cubes across a 1 x 1 section, in four
/// phases along x: hex8, tet4 (6 per cube), prism6 and pyramid5.
Mesh mixed_beam(std::array<int, 3> cells) {
  BeamSpec spec;
  spec.dim = 3;
  spec.cells = cells;
  spec.size = {double(cells[0]), 1, 1};
  spec.phases = {{"hex8", 0.25}, {"tet6", 0.25}, {"prism6", 0.25}, {"pyramid5", 0.25}};
  return make_beam(spec);
}

/// Forces and tangent bitwise equal on one and on two threads.
void expect_same_on_one_and_two_threads(const Model& model, const Assembler& assembler) {
  const std::vector<double> u = wavy_displacement(model.dof_count(), 0.01);
  std::vector<double> g1(model.dof_count()), g2(model.dof_count());
  SparseMatrix K1 = assembler.pattern(), K2 = assembler.pattern();
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  assembler.assemble(u, g1, &K1);
  omp_set_num_threads(2);
  assembler.assemble(u, g2, &K2);
  omp_set_num_threads(threads);
  EXPECT_EQ(g1, g2);
  EXPECT_EQ(K1.values, K2.values);
}

TEST(Assembler, TangentIsTheDerivativeOfTheForcesOnAMixedBeam) {
  const Mesh mesh = mixed_beam({4, 1, 1});
  const Model model(mesh, test::cantilever("stvk").model);
  const Assembler assembler(model);
  EXPECT_LT(test::tangent_error(model, assembler, wavy_displacement(model.dof_count(), 0.02)), 1e-6);
}

/// Largest |a - b| over the largest |b|.
double relative_difference(std::span<const double> a, std::span<const double> b) {
  double worst = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    worst = std::max(worst, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(b[i]));
  }
  return worst / scale;
}

/// The tangent (free dofs by free dofs, dense) summed cell by cell from the
/// kernels, without the assembler's pattern or scatter maps.
std::vector<double> dense_tangent(const Model& model, std::span<const double> u) {
  const int n = model.free_dof_count(), d = model.dim();
  std::vector<double> K(static_cast<std::size_t>(n) * n, 0.0);
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const tm_kernel& kernel = model.kernel(cell);
    std::vector<double> local(kernel.dofs), g(kernel.dofs), k(static_cast<std::size_t>(kernel.dofs) * kernel.dofs);
    model.gather(cell, u, local.data());
    kernel.gradient_hessian(local.data(), model.consts(cell), g.data(), k.data());
    const auto nodes = model.cell_nodes(cell);
    for (int i = 0; i < kernel.dofs; ++i)
      for (int j = 0; j < kernel.dofs; ++j) {
        const int row = model.free_index()[nodes[i / d] * d + i % d];
        const int column = model.free_index()[nodes[j / d] * d + j % d];
        if (row >= 0 && column >= 0) K[static_cast<std::size_t>(row) * n + column] += k[i * kernel.dofs + j];
      }
  }
  return K;
}

/// The assembled tangent equals the dense cell-by-cell sum, where nodes
/// are fully fixed (the clamp), partly fixed (`partial` components at the
/// tip: the per-entry scatter) and free (the node-block scatter).
void expect_tangent_matches_dense_sum(const Mesh& mesh, std::array<bool, 3> partial) {
  Scene scene = test::cantilever("stvk");
  PrescribedSpec tip;
  tip.region = "tip";
  tip.components = partial;
  scene.model.prescribed = {tip};
  const Model model(mesh, scene.model);
  const Assembler assembler(model, false);
  const std::vector<double> u = wavy_displacement(model.dof_count(), 0.02);
  std::vector<double> g(model.dof_count());
  SparseMatrix K = assembler.pattern();
  assembler.assemble(u, g, &K);
  const std::vector<double> reference = dense_tangent(model, u);
  const int n = model.free_dof_count();
  std::vector<double> assembled(reference.size(), 0.0);
  for (int row = 0; row < n; ++row)
    for (int k = K.row_start[row]; k < K.row_start[row + 1]; ++k)
      assembled[static_cast<std::size_t>(row) * n + K.columns[k]] = K.values[k];
  EXPECT_LT(relative_difference(assembled, reference), 1e-14);
  EXPECT_LT(n, model.dof_count() - 1);  // the clamp and the tip's fixed components left out
}

TEST(Assembler, TangentMatchesTheCellByCellSumWithPartlyFixedNodes) {
  expect_tangent_matches_dense_sum(mixed_beam({4, 2, 2}), {true, false, true});
  expect_tangent_matches_dense_sum(mixed_beam({4, 2, 2}), {false, true, false});
  expect_tangent_matches_dense_sum(test::beam(2, "quad4", {6, 2, 1}), {true, false, false});
  expect_tangent_matches_dense_sum(test::beam(2, "tri3", {6, 2, 1}), {false, true, false});
}

TEST(Assembler, ScatterByNodeBlocksGivesTheSameBitsAsByEntries) {
  Scene scene = test::cantilever("stvk");
  PrescribedSpec tip;
  tip.region = "tip";
  tip.components = {false, true, false};
  scene.model.prescribed = {tip};
  for (const Mesh& mesh : {test::beam(3, "tet6", {20, 6, 6}), test::beam(2, "quad4", {6, 2, 1})}) {
    const Model model(mesh, scene.model);
    Assembler assembler(model);
    const std::vector<double> u = wavy_displacement(model.dof_count(), 0.02);
    std::vector<double> g_blocks(model.dof_count()), g_entries(model.dof_count());
    SparseMatrix by_blocks = assembler.pattern(), by_entries = assembler.pattern();
    const std::size_t block_bytes = assembler.scatter_map_bytes();
    assembler.assemble(u, g_blocks, &by_blocks);
    assembler.set_scatter_by_blocks(false);
    assembler.assemble(u, g_entries, &by_entries);
    EXPECT_EQ(by_blocks.values, by_entries.values);
    EXPECT_EQ(g_blocks, g_entries);
    EXPECT_LT(block_bytes, assembler.scatter_map_bytes() / 2);
  }
}

TEST(Assembler, PatternIsSymmetricWithEveryDiagonal) {
  const Mesh mesh = test::beam(2, "tri3", {6, 2, 1});
  const Model model(mesh, test::cantilever("hooke").model);
  const Assembler assembler(model);
  const SparseMatrix& K = assembler.pattern();
  for (int row = 0; row < K.rows; ++row) {
    EXPECT_GE(K.diagonal[row], 0);
    for (int k = K.row_start[row]; k < K.row_start[row + 1]; ++k) {
      const int column = K.columns[k];
      bool mirrored = false;
      for (int m = K.row_start[column]; m < K.row_start[column + 1]; ++m) mirrored |= K.columns[m] == row;
      EXPECT_TRUE(mirrored) << row << "," << column;
    }
  }
}

TEST(Assembler, OneAndTwoThreadsGiveIdenticalResults) {
  // 4320 tets: above the threshold where assembly goes parallel.
  const Mesh mesh = test::beam(3, "tet6", {20, 6, 6});
  const Model model(mesh, test::cantilever("stvk").model);
  const Assembler assembler(model);
  expect_same_on_one_and_two_threads(model, assembler);
  EXPECT_GT(assembler.colour_count(), 1);
}

/// The folded assembly against every cell's kernel, forces over all dofs
/// (clamped ones included) and the tangent, to round-off.
void expect_folded_matches_per_cell(const Model& model, const Assembler& folded, const Assembler& per_cell,
                                    std::span<const double> u) {
  std::vector<double> g1(model.dof_count()), g2(model.dof_count());
  SparseMatrix K1 = folded.pattern(), K2 = per_cell.pattern();
  folded.assemble(u, g1, &K1);
  per_cell.assemble(u, g2, &K2);
  EXPECT_LT(relative_difference(g1, g2), 1e-13);
  EXPECT_LT(relative_difference(K1.values, K2.values), 1e-13);
  folded.assemble(u, g1, nullptr);
  EXPECT_LT(relative_difference(g1, g2), 1e-13);
}

TEST(Assembler, FoldedHookeCellsGiveThePerCellForcesAndTangent) {
  const Mesh mesh = mixed_beam({4, 2, 2});
  const Model model(mesh, test::cantilever("hooke").model);
  const Assembler folded(model), per_cell(model, false);
  const std::vector<double> u = wavy_displacement(model.dof_count(), 0.02);
  expect_folded_matches_per_cell(model, folded, per_cell, u);
  EXPECT_EQ(folded.folded_cell_count(), model.cell_count());
  EXPECT_EQ(per_cell.folded_cell_count(), 0);
}

TEST(Assembler, FoldedPartFollowsLawSwitchesAndBlends) {
  const Mesh mesh = test::beam(2, "quad4", {8, 2, 1});
  Model model(mesh, test::cantilever("hooke").model);
  const Assembler folded(model), per_cell(model, false);
  const std::vector<double> u = wavy_displacement(model.dof_count(), 0.05);
  expect_folded_matches_per_cell(model, folded, per_cell, u);
  for (int cell = 0; cell < model.cell_count(); cell += 3) model.set_law(cell, "stvk");
  expect_folded_matches_per_cell(model, folded, per_cell, u);
  const int stvk_cells = (model.cell_count() + 2) / 3;
  EXPECT_EQ(folded.folded_cell_count(), model.cell_count() - stvk_cells);
  // Back to Hooke with a blend: blending cells run their kernels until the blend ends.
  const tm_kernel* stvk = &model.kernel(0);
  model.set_law(0, "hooke");
  model.start_blend(0, stvk);
  model.set_blend_weight(0, 0.5);
  expect_folded_matches_per_cell(model, folded, per_cell, u);
  EXPECT_EQ(folded.folded_cell_count(), model.cell_count() - stvk_cells);
  model.set_blend_weight(0, 1.0);
  expect_folded_matches_per_cell(model, folded, per_cell, u);
  EXPECT_EQ(folded.folded_cell_count(), model.cell_count() - stvk_cells + 1);
  for (int cell = 0; cell < model.cell_count(); ++cell) model.set_law(cell, "stvk");
  expect_folded_matches_per_cell(model, folded, per_cell, u);
  EXPECT_EQ(folded.folded_cell_count(), 0);
  // Every switch in or out of the linear set was counted once.
  EXPECT_EQ(folded.folding_changes(), model.cell_count() + stvk_cells + 1 + (model.cell_count() - stvk_cells + 1));
}

/// When most cells leave the linear set, the folded product runs over the
/// rows of the nodes the remaining folded cells hold, and the blocks of the
/// other nodes are exact zeros (not the round-off of the subtractions), so
/// the forces are those of the per-cell assembly and nothing leaks from the
/// nodes no folded cell holds.
TEST(Assembler, FoldedPartSkipsAndZeroesTheNodesNoFoldedCellHolds) {
  const Mesh mesh = test::beam(3, "tet6", {10, 2, 2});
  Model model(mesh, test::cantilever("hooke").model);
  const Assembler folded(model), per_cell(model, false);
  const std::vector<double> u = wavy_displacement(model.dof_count(), 0.05);
  expect_folded_matches_per_cell(model, folded, per_cell, u);  // everything folded, then 80 % unfolded
  const auto first_node_x = [&](int cell) { return mesh.rest_positions[3 * model.cell_nodes(cell)[0]]; };
  for (int cell = 0; cell < model.cell_count(); ++cell)
    if (first_node_x(cell) > 0.5) model.set_law(cell, "stvk");
  expect_folded_matches_per_cell(model, folded, per_cell, u);
  ASSERT_GT(folded.folded_cell_count(), 0);
  ASSERT_LT(folded.folded_cell_count(), model.cell_count() / 4);  // a fifth of the nodes: the rows are skipped
  std::vector<bool> held(mesh.node_count(), false);
  for (int cell = 0; cell < model.cell_count(); ++cell)
    if (folded.linear_part()->folded(cell))
      for (int node : model.cell_nodes(cell)) held[node] = true;
  // u on the nodes no folded cell holds: the folded forces are exactly zero everywhere.
  std::vector<double> outside(model.dof_count(), 0.0), g(model.dof_count(), 1.0);
  for (int node = 0; node < mesh.node_count(); ++node)
    if (!held[node])
      for (int a = 0; a < 3; ++a) outside[3 * node + a] = u[3 * node + a];
  folded.linear_part()->multiply(outside, g);
  for (double value : g) ASSERT_EQ(value, 0.0);
  // And back: every cell folded again.
  for (int cell = 0; cell < model.cell_count(); ++cell) model.set_law(cell, "hooke");
  expect_folded_matches_per_cell(model, folded, per_cell, u);
  EXPECT_EQ(folded.folded_cell_count(), model.cell_count());
}

/// A model with no linear cell holds no folded blocks; the first cell that
/// switches to Hooke allocates them, and the forces and tangent still
/// match the per-cell assembly.
TEST(Assembler, FoldedBlocksAreAllocatedAtTheFirstFold) {
  const Mesh mesh = test::beam(2, "quad4", {8, 2, 1});
  Model model(mesh, test::cantilever("stvk").model);
  const Assembler folded(model), per_cell(model, false);
  const std::vector<double> u = wavy_displacement(model.dof_count(), 0.05);
  expect_folded_matches_per_cell(model, folded, per_cell, u);
  EXPECT_TRUE(folded.linear_part()->saved().blocks.empty());
  model.set_law(5, "hooke");
  expect_folded_matches_per_cell(model, folded, per_cell, u);
  EXPECT_EQ(folded.folded_cell_count(), 1);
  EXPECT_FALSE(folded.linear_part()->saved().blocks.empty());
}

/// Largest difference between the batched and the per-element assembly
/// (forces and tangent), relative to the largest entry.
double batched_against_per_element(const Model& model, Assembler& assembler, const std::vector<double>& u) {
  std::vector<double> g_batched(model.dof_count()), g_single(model.dof_count());
  SparseMatrix K_batched = assembler.pattern(), K_single = assembler.pattern();
  assembler.set_batched(true);
  assembler.assemble(u, g_batched, &K_batched);
  assembler.set_batched(false);
  assembler.assemble(u, g_single, &K_single);
  assembler.set_batched(true);
  double worst = 0, scale = 0;
  for (std::size_t i = 0; i < g_single.size(); ++i) {
    worst = std::max(worst, std::abs(g_batched[i] - g_single[i]));
    scale = std::max(scale, std::abs(g_single[i]));
  }
  for (std::size_t i = 0; i < K_single.values.size(); ++i) {
    worst = std::max(worst, std::abs(K_batched.values[i] - K_single.values[i]));
    scale = std::max(scale, std::abs(K_single.values[i]));
  }
  return scale > 0 ? worst / scale : worst;
}

TEST(Assembler, BatchedKernelsGiveThePerElementForcesAndTangent) {
  // Four element types in runs of every length, laws interleaved so that
  // batches break on kernel changes, and a blending cell in a run.
  const Mesh mesh = mixed_beam({6, 2, 2});
  Model model(mesh, test::cantilever("stvk").model);
  Assembler assembler(model, false);
  EXPECT_TRUE(assembler.batched());
  const std::vector<double> u = wavy_displacement(model.dof_count(), 0.03);
  EXPECT_LT(batched_against_per_element(model, assembler, u), 1e-13);
  for (int cell = 0; cell < model.cell_count(); cell += 5) model.set_law(cell, "neohookean");
  const tm_kernel* before = &model.kernel(7);
  model.set_law(7, "corotational");
  model.start_blend(7, before);
  model.set_blend_weight(7, 0.25);
  EXPECT_LT(batched_against_per_element(model, assembler, u), 1e-13);
  assembler.set_hessian_projection(true);
  EXPECT_LT(batched_against_per_element(model, assembler, u), 1e-13);
  // The forces alone (explicit integration) go through the batched gradient.
  std::vector<double> g_batched(model.dof_count()), g_single(model.dof_count());
  assembler.assemble(u, g_batched, nullptr);
  assembler.set_batched(false);
  assembler.assemble(u, g_single, nullptr);
  double worst = 0, scale = 0;
  for (std::size_t i = 0; i < g_single.size(); ++i) {
    worst = std::max(worst, std::abs(g_batched[i] - g_single[i]));
    scale = std::max(scale, std::abs(g_single[i]));
  }
  EXPECT_LT(worst, 1e-13 * scale);
}

TEST(Assembler, BatchedKernelsGiveThePerElementForcesAndTangentIn2D) {
  // Triangles and quadrilaterals, linear and quadratic (the batch packing has
  // compile-time loops for tri3 and quad4, a general one for the others),
  // three laws interleaved so that batches of each fill and run partly empty.
  for (const int order : {1, 2}) {
    BeamSpec spec;
    spec.cells = {8, 3, 1};
    spec.size = {8.0, 1.0, 1.0};
    spec.phases = {{"tri3", 0.5}, {"quad4", 0.5}};
    spec.order = order;
    const Mesh mesh = make_beam(spec);
    Model model(mesh, test::cantilever("stvk").model);
    for (int cell = 0; cell < model.cell_count(); ++cell)
      if (cell % 3 == 1) model.set_law(cell, cell % 2 ? "neohookean" : "corotational");
    Assembler assembler(model, false);
    const std::vector<double> u = wavy_displacement(model.dof_count(), 0.03);
    EXPECT_LT(batched_against_per_element(model, assembler, u), 1e-13) << "order " << order;
  }
}

TEST(Assembler, BatchedAssemblyIsIdenticalOnOneAndTwoThreads) {
  const Mesh mesh = test::beam(3, "tet6", {20, 6, 6});
  Model model(mesh, test::cantilever("stvk").model);
  for (int cell = 0; cell < model.cell_count(); cell += 7) model.set_law(cell, "neohookean");
  const Assembler assembler(model);
  expect_same_on_one_and_two_threads(model, assembler);
}

TEST(Assembler, FoldedAssemblyIsIdenticalOnOneAndTwoThreads) {
  // 4320 tets, a third of them StVK: both the block product and the kernels go parallel.
  const Mesh mesh = test::beam(3, "tet6", {20, 6, 6});
  Model model(mesh, test::cantilever("hooke").model);
  for (int cell = 0; cell < model.cell_count(); cell += 3) model.set_law(cell, "stvk");
  const Assembler assembler(model);
  expect_same_on_one_and_two_threads(model, assembler);
}

}  // namespace
}  // namespace tensormass

namespace tensormass {
namespace {

/// Central difference of the assembled energy along `direction` against
/// g(u).direction, relative to the size of the forces.
double energy_slope_error(const Assembler& assembler, const Model& model, const std::vector<double>& u,
                          const std::vector<double>& direction) {
  std::vector<double> g(model.dof_count());
  assembler.assemble(u, g, nullptr);
  const double h = 1e-6;
  std::vector<double> ahead = u, behind = u;
  for (std::size_t i = 0; i < u.size(); ++i) ahead[i] += h * direction[i], behind[i] -= h * direction[i];
  const double slope = (assembler.energy(ahead) - assembler.energy(behind)) / (2 * h);
  double exact = 0, scale = 0;
  for (std::size_t i = 0; i < u.size(); ++i) exact += g[i] * direction[i], scale += std::abs(g[i] * direction[i]);
  return std::abs(slope - exact) / scale;
}

TEST(Assembler, EnergyIsThePotentialOfTheAssembledForcesWithFoldedAndBlendingCells) {
  const Mesh mesh = test::beam(2, "quad4", {8, 2, 1});
  Model model(mesh, test::cantilever("hooke").model);
  const Assembler folded(model), per_cell(model, false);
  const std::vector<double> u = wavy_displacement(model.dof_count(), 0.05);
  const std::vector<double> direction = wavy_displacement(model.dof_count(), 1.0);
  for (int cell = 0; cell < model.cell_count(); cell += 3) model.set_law(cell, "stvk");
  const tm_kernel* stvk = &model.kernel(0);
  model.set_law(0, "neohookean");
  model.start_blend(0, stvk);
  model.set_blend_weight(0, 0.3);
  EXPECT_LT(energy_slope_error(folded, model, u, direction), 1e-7);
  // Folding changes the summation, not the value.
  EXPECT_NEAR(folded.energy(u), per_cell.energy(u), 1e-12 * std::abs(per_cell.energy(u)));
  // Without blends it is the model's total strain energy.
  model.set_blend_weight(0, 1.0);
  EXPECT_NEAR(folded.energy(u), model.strain_energy(u), 1e-12 * std::abs(model.strain_energy(u)));
}

TEST(Assembler, EnergyIsIdenticalOnOneAndTwoThreads) {
  const Mesh mesh = test::beam(3, "tet6", {20, 6, 6});
  Model model(mesh, test::cantilever("stvk").model);
  const Assembler assembler(model);
  const std::vector<double> u = wavy_displacement(model.dof_count(), 0.01);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const double one = assembler.energy(u);
  omp_set_num_threads(2);
  const double two = assembler.energy(u);
  omp_set_num_threads(threads);
  EXPECT_EQ(one, two);
}

/// The smallest of x.K x / x.x over a few wavy vectors x of the free dofs.
double smallest_rayleigh_quotient(const SparseMatrix& K) {
  double smallest = INFINITY;
  for (int k = 1; k <= 20; ++k) {
    std::vector<double> x(K.rows), y(K.rows);
    for (int i = 0; i < K.rows; ++i) x[i] = std::sin(0.37 * k * i + k);
    K.multiply(x, y);
    double xKx = 0, xx = 0;
    for (int i = 0; i < K.rows; ++i) xKx += x[i] * y[i], xx += x[i] * x[i];
    smallest = std::min(smallest, xKx / xx);
  }
  return smallest;
}

TEST(Assembler, ProjectedHessiansGiveAPositiveSemidefiniteTangentUnderCompression) {
  // A StVK beam squashed to 40 % along x: its tangent is indefinite.
  const Mesh mesh = test::beam(3, "tet6", {6, 2, 2});
  const Model model(mesh, test::cantilever("stvk").model);
  Assembler assembler(model);
  std::vector<double> u(model.dof_count(), 0.0), g(model.dof_count());
  for (int node = 0; node < mesh.node_count(); ++node) u[node * 3] = -0.6 * mesh.rest_positions[3 * node];
  SparseMatrix plain = assembler.pattern(), projected = assembler.pattern();
  assembler.assemble(u, g, &plain);
  assembler.set_hessian_projection(true);
  assembler.assemble(u, g, &projected);
  EXPECT_LT(smallest_rayleigh_quotient(plain), 0.0);
  EXPECT_GE(smallest_rayleigh_quotient(projected), 0.0);
  // At rest every element Hessian is positive semi-definite already: unchanged.
  std::vector<double> rest(model.dof_count(), 0.0);
  SparseMatrix at_rest = assembler.pattern(), at_rest_plain = assembler.pattern();
  assembler.assemble(rest, g, &at_rest);
  assembler.set_hessian_projection(false);
  assembler.assemble(rest, g, &at_rest_plain);
  for (std::size_t k = 0; k < at_rest.values.size(); ++k)
    EXPECT_NEAR(at_rest.values[k], at_rest_plain.values[k], 1e-9 * std::abs(at_rest_plain.values[k]) + 1e-6);
}

}  // namespace
}  // namespace tensormass
