// KernelPlan: every kernel cell is planned once, batches hold one kernel
// with its lanes packed, an update plans again only the chunks whose cells
// changed law and then equals a fresh plan; the Assembler follows law
// switches and folding through it.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "support/cantilever.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/assembly/kernel_plan.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

constexpr int kChunkCells = 16;
constexpr int kAssemblerChunkCells = 128;  ///< the Assembler's chunks (assembler.cpp)

/// Every cell batched when its kernel has batched entry points, except every seventh, run alone.
KernelPlan::Mode mode_of(const Model& model, int cell) {
  if (cell % 11 == 3) return KernelPlan::kSkip;
  if (cell % 7 == 0 || model.kernel(cell).batch_width <= 1) return KernelPlan::kSingle;
  return KernelPlan::kBatched;
}

KernelPlan planned(const Model& model) {
  KernelPlan plan;
  plan.update(model, kChunkCells, [&](int cell) { return mode_of(model, cell); });
  return plan;
}

int chunk_count(const Model& model) { return (model.cell_count() + kChunkCells - 1) / kChunkCells; }

/// Two plans hold the same steps, batches, lanes and constants.
void expect_same_plans(const Model& model, const KernelPlan& a, const KernelPlan& b) {
  for (int chunk = 0; chunk < chunk_count(model); ++chunk) {
    ASSERT_EQ(a.steps(chunk).size(), b.steps(chunk).size()) << "chunk " << chunk;
    for (std::size_t s = 0; s < a.steps(chunk).size(); ++s) {
      const KernelPlan::Step sa = a.steps(chunk)[s], sb = b.steps(chunk)[s];
      ASSERT_EQ(sa.cell, sb.cell);
      ASSERT_EQ(sa.batch, sb.batch);
      if (sa.batch < 0) continue;
      const KernelPlan::Batch &ba = a.batch(chunk, sa.batch), &bb = b.batch(chunk, sb.batch);
      ASSERT_EQ(ba.kernel, bb.kernel);
      ASSERT_EQ(ba.size, bb.size);
      const int width = ba.kernel->batch_width;
      for (int lane = 0; lane < ba.size; ++lane) EXPECT_EQ(ba.cells[lane], bb.cells[lane]);
      for (int i = 0; i < ba.kernel->nodes * width; ++i) EXPECT_EQ(a.dofs(chunk, ba)[i], b.dofs(chunk, bb)[i]);
      for (int i = 0; i < ba.kernel->consts * width; ++i) EXPECT_EQ(a.consts(chunk, ba)[i], b.consts(chunk, bb)[i]);
    }
  }
}

TEST(KernelPlan, PlansEveryKernelCellOnceWithItsLanesPacked) {
  const Mesh mesh = test::beam(3, "tet6", {6, 2, 2});
  Model model(mesh, test::cantilever("stvk").model);
  for (int cell = 0; cell < model.cell_count(); cell += 3) model.set_law(cell, "neohookean");
  const KernelPlan plan = planned(model);
  std::vector<int> seen(model.cell_count(), 0);
  for (int chunk = 0; chunk < chunk_count(model); ++chunk)
    for (const KernelPlan::Step& step : plan.steps(chunk)) {
      if (step.batch < 0) {
        EXPECT_EQ(mode_of(model, step.cell), KernelPlan::kSingle);
        ++seen[step.cell];
        continue;
      }
      const KernelPlan::Batch& batch = plan.batch(chunk, step.batch);
      const int width = batch.kernel->batch_width, d = model.dim();
      ASSERT_GE(batch.size, 1);
      ASSERT_LE(batch.size, width);
      for (int lane = 0; lane < width; ++lane) {
        const int cell = batch.cells[lane < batch.size ? lane : 0];  // lanes past the size repeat the first cell
        EXPECT_EQ(cell / kChunkCells, chunk);
        EXPECT_EQ(&model.kernel(cell), batch.kernel);
        EXPECT_EQ(mode_of(model, cell), KernelPlan::kBatched);
        if (lane < batch.size) ++seen[cell];
        for (int j = 0; j < batch.kernel->nodes; ++j)
          EXPECT_EQ(plan.dofs(chunk, batch)[j * width + lane], d * model.cell_nodes(cell)[j]);
        for (int i = 0; i < batch.kernel->consts; ++i)
          EXPECT_EQ(plan.consts(chunk, batch)[i * width + lane], model.consts(cell)[i]);
      }
    }
  for (int cell = 0; cell < model.cell_count(); ++cell)
    EXPECT_EQ(seen[cell], mode_of(model, cell) == KernelPlan::kSkip ? 0 : 1) << "cell " << cell;
}

TEST(KernelPlan, AnUpdatePlansAgainOnlyTheChunksThatChangedAndEqualsAFreshPlan) {
  const Mesh mesh = test::beam(3, "tet6", {6, 2, 2});
  Model model(mesh, test::cantilever("stvk").model);
  KernelPlan plan = planned(model);
  const int chunks = chunk_count(model);
  EXPECT_EQ(plan.replanned_chunks(), chunks);
  plan.update(model, kChunkCells, [&](int cell) { return mode_of(model, cell); });
  EXPECT_EQ(plan.replanned_chunks(), chunks);          // nothing changed
  model.set_law(5, "neohookean");                      // chunk 0
  model.set_law(3 * kChunkCells + 2, "corotational");  // chunk 3
  plan.update(model, kChunkCells, [&](int cell) { return mode_of(model, cell); });
  EXPECT_EQ(plan.replanned_chunks(), chunks + 2);
  expect_same_plans(model, plan, planned(model));
  model.set_law(5, "stvk");  // back: the chunk's plan is the first one again
  plan.update(model, kChunkCells, [&](int cell) { return mode_of(model, cell); });
  EXPECT_EQ(plan.replanned_chunks(), chunks + 3);
  expect_same_plans(model, plan, planned(model));
}

/// The Assembler's forces and tangent after law switches, and a fresh
/// assembler's on the same laws: bitwise equal. The fresh one takes the
/// used one's folded part (whose sums depend on the order of the switches).
void expect_same_as_a_fresh_assembler(const Model& model, const Assembler& used) {
  std::vector<double> u(model.dof_count());
  for (int i = 0; i < model.dof_count(); ++i) u[i] = 0.02 * std::sin(0.37 * i + 0.1);
  std::vector<double> g(model.dof_count());
  used.assemble(u, g, nullptr);  // brings the used part up to date
  Assembler fresh(model);
  fresh.set_batched(used.batched());
  fresh.linear_part()->restore(used.linear_part()->saved());
  std::vector<double> g_used(model.dof_count()), g_fresh(model.dof_count());
  SparseMatrix K_used = used.pattern(), K_fresh = fresh.pattern();
  used.assemble(u, g_used, &K_used);
  fresh.assemble(u, g_fresh, &K_fresh);
  EXPECT_EQ(g_used, g_fresh);
  EXPECT_EQ(K_used.values, K_fresh.values);
  used.assemble(u, g_used, nullptr);
  fresh.assemble(u, g_fresh, nullptr);
  EXPECT_EQ(g_used, g_fresh);
}

TEST(KernelPlan, TheAssemblerFollowsLawSwitchesFoldingAndBlends) {
  const Mesh mesh = test::beam(3, "tet6", {6, 2, 2});
  Model model(mesh, test::cantilever("hooke").model);
  Assembler assembler(model);
  expect_same_as_a_fresh_assembler(model, assembler);  // every cell folded
  for (int cell = 0; cell < model.cell_count(); cell += 4) model.set_law(cell, "neohookean");
  expect_same_as_a_fresh_assembler(model, assembler);  // unfolded cells, batched
  for (int cell = 0; cell < model.cell_count(); cell += 8) model.set_law(cell, "stvk");
  model.set_law(1, "corotational");
  expect_same_as_a_fresh_assembler(model, assembler);  // three kernels interleaved
  const tm_kernel* before = &model.kernel(9);
  model.set_law(9, "neohookean");
  model.start_blend(9, before);
  model.set_blend_weight(9, 0.5);
  expect_same_as_a_fresh_assembler(model, assembler);  // a blending cell runs alone
  model.set_blend_weight(9, 1.0);
  for (int cell = 0; cell < model.cell_count(); cell += 8) model.set_law(cell, "hooke");
  expect_same_as_a_fresh_assembler(model, assembler);  // folded again
  assembler.set_batched(false);
  expect_same_as_a_fresh_assembler(model, assembler);
  const KernelPlan& plan = assembler.kernel_plan();
  int single = 0;
  for (int chunk = 0; chunk * kAssemblerChunkCells < model.cell_count(); ++chunk)
    for (const KernelPlan::Step& step : plan.steps(chunk)) {
      EXPECT_LT(step.batch, 0);  // every cell alone, though no law changed
      ++single;
    }
  EXPECT_GT(single, 0);
  assembler.set_batched(true);
  expect_same_as_a_fresh_assembler(model, assembler);
}

}  // namespace
}  // namespace tensormass
