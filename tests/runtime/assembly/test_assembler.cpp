// Assembly: the sparse tangent is the derivative of the assembled forces,
// and results do not depend on the number of threads.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>

#include "support/cantilever.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

std::vector<double> wavy_displacement(int dofs, double amplitude) {
  std::vector<double> u(dofs);
  for (int i = 0; i < dofs; ++i) u[i] = amplitude * std::sin(0.7 * i + 0.3);
  return u;
}

double entry(const SparseMatrix& K, int row, int column) {
  for (int k = K.row_start[row]; k < K.row_start[row + 1]; ++k)
    if (K.columns[k] == column) return K.values[k];
  return 0.0;
}

TEST(Assembler, TangentIsTheDerivativeOfTheForcesOnAMixedBeam) {
  BeamSpec spec;
  spec.dim = 3;
  spec.cells = {4, 1, 1};
  spec.size = {4, 1, 1};
  spec.phases = {{"hex8", 0.25}, {"tet6", 0.25}, {"prism6", 0.25}, {"pyramid5", 0.25}};
  const Mesh mesh = make_beam(spec);
  const Model model(mesh, test::cantilever("stvk").model);
  const Assembler assembler(model);
  std::vector<double> u = wavy_displacement(model.dof_count(), 0.02), g(model.dof_count()), gp(g), gm(g);
  SparseMatrix K = assembler.pattern();
  assembler.assemble(u, g, &K);
  const double h = 1e-6;
  double worst = 0, scale = 0;
  for (int column = 0; column < model.free_dof_count(); ++column) {
    const int dof = model.free_dofs()[column];
    std::vector<double> up = u, um = u;
    up[dof] += h;
    um[dof] -= h;
    assembler.assemble(up, gp, nullptr);
    assembler.assemble(um, gm, nullptr);
    for (int row = 0; row < model.free_dof_count(); ++row) {
      const int r = model.free_dofs()[row];
      const double fd = (gp[r] - gm[r]) / (2 * h);
      worst = std::max(worst, std::abs(fd - entry(K, row, column)));
      scale = std::max(scale, std::abs(fd));
    }
  }
  EXPECT_LT(worst, 1e-6 * scale);
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
  EXPECT_GT(assembler.colour_count(), 1);
}

}  // namespace
}  // namespace tensormass
