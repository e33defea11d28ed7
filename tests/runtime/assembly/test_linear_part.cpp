// The folded linear part of the internal forces (tensormass/assembly/linear_part.hpp)
// on its own: K_L equal to the per-cell Hessians summed densely, symmetric,
// its free rows copied into the tangent's pattern, update() folding only on
// law changes, and a checkpoint taken back bringing it to the same bits as
// the interrupted part. (Folding against the per-cell assembly through law
// switches, blends and skipped rows: test_assembler.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "support/cantilever.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/assembly/linear_part.hpp"
#include "tensormass/assembly/node_graph.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

/// The dense dof_count by dof_count sum of the Hessians of the Hooke cells.
std::vector<double> dense_hooke_sum(const Model& model) {
  const std::size_t n = static_cast<std::size_t>(model.dof_count());
  std::vector<double> K(n * n, 0.0);
  const int d = model.dim();
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const tm_kernel& kernel = model.kernel(cell);
    if (!kernel.linear) continue;
    std::vector<double> zero(kernel.dofs, 0.0), Ke(static_cast<std::size_t>(kernel.dofs) * kernel.dofs);
    kernel.hessian(zero.data(), model.consts(cell), Ke.data());
    const auto nodes = model.cell_nodes(cell);
    for (int i = 0; i < kernel.dofs; ++i)
      for (int j = 0; j < kernel.dofs; ++j) {
        const std::size_t row = static_cast<std::size_t>(nodes[i / d] * d + i % d);
        const std::size_t column = static_cast<std::size_t>(nodes[j / d] * d + j % d);
        K[row * n + column] += Ke[static_cast<std::size_t>(i) * kernel.dofs + j];
      }
  }
  return K;
}

std::vector<double> wavy(int size, double phase) {
  std::vector<double> u(static_cast<std::size_t>(size));
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = std::sin(0.37 * static_cast<double>(i) + phase);
  return u;
}

double largest(const std::vector<double>& values) {
  double m = 0;
  for (double v : values) m = std::max(m, std::abs(v));
  return m;
}

/// A model, its node graph and free pattern, and a linear part on them.
struct Folding {
  explicit Folding(const std::string& law, int dim = 2)
      : mesh(dim == 2 ? test::beam(2, "quad4", {6, 2, 1}) : test::beam(3, "tet6", {3, 1, 1})),
        model(mesh, test::cantilever(law).model),
        graph(make_node_graph(model)),
        pattern(Assembler(model, false).pattern()),
        part(model, graph, pattern) {}
  std::vector<double> product(const std::vector<double>& u) const {
    std::vector<double> g(u.size(), 7.0);
    part.multiply(u, g);
    return g;
  }
  Mesh mesh;
  Model model;
  NodeGraph graph;
  SparseMatrix pattern;
  LinearPart part;
};

TEST(LinearPart, TheProductIsTheSumOfTheCellsHessians) {
  for (int dim : {2, 3}) {
    Folding f("hooke", dim);
    EXPECT_EQ(f.part.update(), f.model.cell_count());
    EXPECT_EQ(f.part.folded_count(), f.model.cell_count());
    const std::vector<double> K = dense_hooke_sum(f.model);
    const std::vector<double> u = wavy(f.model.dof_count(), 0.3);
    const std::vector<double> g = f.product(u);
    const std::size_t n = u.size();
    std::vector<double> expected(n, 0.0);
    for (std::size_t r = 0; r < n; ++r)
      for (std::size_t c = 0; c < n; ++c) expected[r] += K[r * n + c] * u[c];
    const double scale = largest(expected);
    for (std::size_t r = 0; r < n; ++r) EXPECT_NEAR(g[r], expected[r], 1e-12 * scale) << dim << "D row " << r;
  }
}

TEST(LinearPart, TheFoldedMatrixIsSymmetric) {
  Folding f("hooke", 3);
  f.part.update();
  const std::vector<double> u = wavy(f.model.dof_count(), 0.1), v = wavy(f.model.dof_count(), 2.0);
  const std::vector<double> Ku = f.product(u), Kv = f.product(v);
  double vKu = 0, uKv = 0;
  for (std::size_t i = 0; i < u.size(); ++i) {
    vKu += v[i] * Ku[i];
    uKv += u[i] * Kv[i];
  }
  EXPECT_NEAR(vKu, uKv, 1e-12 * std::abs(vKu));
}

TEST(LinearPart, CopyFreeGivesTheFreeRowsAndColumnsInThePattern) {
  Folding f("hooke");
  f.part.update();
  const std::vector<double> K = dense_hooke_sum(f.model);
  const std::size_t n = static_cast<std::size_t>(f.model.dof_count());
  SparseMatrix free = f.pattern;
  f.part.copy_free(free.values);
  const auto& dofs = f.model.free_dofs();
  for (int row = 0; row < free.rows; ++row)
    for (int k = free.row_start[row]; k < free.row_start[row + 1]; ++k) {
      const std::size_t r = static_cast<std::size_t>(dofs[row]), c = static_cast<std::size_t>(dofs[free.columns[k]]);
      EXPECT_NEAR(free.values[k], K[r * n + c], 1e-9 * largest(K)) << r << ", " << c;
    }
}

TEST(LinearPart, UpdateFoldsOnlyWhenTheLawsChanged) {
  Folding f("hooke");
  EXPECT_EQ(f.part.update(), f.model.cell_count());
  EXPECT_EQ(f.part.update(), 0);  // nothing changed
  f.model.set_law(2, "stvk");
  f.model.set_law(7, "stvk");
  EXPECT_EQ(f.part.update(), 2);
  EXPECT_FALSE(f.part.folded(2));
  EXPECT_TRUE(f.part.folded(3));
  EXPECT_EQ(f.part.folded_count(), f.model.cell_count() - 2);
  EXPECT_EQ(f.part.changes(), f.model.cell_count() + 2);
}

TEST(LinearPart, NothingFoldedGivesZeroForces) {
  Folding f("stvk");
  EXPECT_EQ(f.part.update(), 0);
  EXPECT_EQ(f.part.folded_count(), 0);
  for (double value : f.product(wavy(f.model.dof_count(), 0.0))) EXPECT_EQ(value, 0.0);
}

TEST(LinearPart, ACheckpointTakenBackUpdatesToTheSameBits) {
  Folding interrupted("hooke");
  interrupted.part.update();
  interrupted.model.set_law(1, "stvk");
  interrupted.model.set_law(4, "stvk");
  interrupted.part.update();
  interrupted.model.set_law(1, "hooke");  // switched, not yet folded back when saved
  const LinearPart::Saved saved = interrupted.part.saved();
  LinearPart resumed(interrupted.model, interrupted.graph, interrupted.pattern);
  resumed.restore(saved);
  EXPECT_EQ(resumed.folded_count(), interrupted.part.folded_count());
  EXPECT_EQ(interrupted.part.update(), 1);
  EXPECT_EQ(resumed.update(), 1);
  EXPECT_EQ(resumed.saved().blocks, interrupted.part.saved().blocks);
  EXPECT_EQ(resumed.changes(), interrupted.part.changes());
  const std::vector<double> u = wavy(interrupted.model.dof_count(), 1.0);
  std::vector<double> g(u.size());
  resumed.multiply(u, g);
  EXPECT_EQ(g, interrupted.product(u));
}

TEST(LinearPart, ACheckpointOfAnotherModelIsRefused) {
  Folding small("hooke");
  small.part.update();
  Folding other("hooke", 3);
  try {
    other.part.restore(small.part.saved());
    ADD_FAILURE() << "a checkpoint of another model was taken";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "LinearPart::restore: saved for another model");
  }
}

}  // namespace
}  // namespace tensormass
