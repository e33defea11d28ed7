/// \file assembly_checks.hpp
/// Displacements and finite-difference checks shared by the assembly tests.
#ifndef TENSORMASS_TESTS_SUPPORT_ASSEMBLY_CHECKS_HPP
#define TENSORMASS_TESTS_SUPPORT_ASSEMBLY_CHECKS_HPP

#include <algorithm>
#include <cmath>
#include <vector>

#include "tensormass/assembly/assembler.hpp"

namespace tensormass::test {

/// dofs displacements amplitude * sin(0.7 i + 0.3): no symmetry a bug could hide behind.
inline std::vector<double> wavy_displacement(int dofs, double amplitude) {
  std::vector<double> u(dofs);
  for (int i = 0; i < dofs; ++i) u[i] = amplitude * std::sin(0.7 * i + 0.3);
  return u;
}

/// K(row, column), 0 outside the pattern.
inline double entry(const SparseMatrix& K, int row, int column) {
  for (int k = K.row_start[row]; k < K.row_start[row + 1]; ++k)
    if (K.columns[k] == column) return K.values[k];
  return 0.0;
}

/// The largest difference between the assembled tangent at u and central
/// differences (step 1e-6) of the assembled forces, over every free row and
/// column, divided by the largest difference quotient.
inline double tangent_error(const Model& model, const Assembler& assembler, const std::vector<double>& u) {
  std::vector<double> g(model.dof_count()), gp(g), gm(g);
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
  return worst / scale;
}

}  // namespace tensormass::test

#endif
