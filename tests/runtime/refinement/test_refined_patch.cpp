// Patch test on a refined mesh: a distorted mixed quad4/tri3 mesh, refined
// locally (children, quad fans, red-green triangles), assembled from the
// Hooke kernels' stiffness (plane strain). The boundary nodes carry an
// exact linear field, the inner ones are solved for: they must get the
// exact field and every cell the same constant stress. A refined mesh the
// kernels reject (an inverted cell) or a wrong transition fails it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "refinement_checks.hpp"
#include "tensormass/kernels/registry.hpp"

namespace {

using refinement_test::position;
using tensormass::HierarchicalMesh;
using tensormass::Mesh;

/// The mixed beam with its inner nodes moved by up to 0.15 in x and y.
Mesh distorted_beam() {
  Mesh mesh = refinement_test::mixed_beam(4, 3);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> shift(-0.15, 0.15);
  for (int node = 0; node < mesh.node_count(); ++node) {
    double* x = &mesh.rest_positions[3 * node];
    if (x[0] > 0 && x[0] < 6 && x[1] > 0 && x[1] < 3) {
      x[0] += shift(random);
      x[1] += shift(random);
    }
  }
  return mesh;
}

/// u = 1e-3 ((2x + y) / 2, (x + 2y) / 2): strain 1e-3, 1e-3, shear 1e-3.
double exact(const double* x, int c) { return c == 0 ? 1e-3 * (2 * x[0] + x[1]) / 2 : 1e-3 * (x[0] + 2 * x[1]) / 2; }

/// Solves A x = b (m by m, row-major) by Gaussian elimination with partial pivoting.
std::vector<double> solve_dense(std::vector<double> A, std::vector<double> b) {
  const std::size_t m = b.size();
  for (std::size_t k = 0; k < m; ++k) {
    std::size_t pivot = k;
    for (std::size_t i = k + 1; i < m; ++i)
      if (std::abs(A[i * m + k]) > std::abs(A[pivot * m + k])) pivot = i;
    for (std::size_t j = 0; j < m; ++j) std::swap(A[k * m + j], A[pivot * m + j]);
    std::swap(b[k], b[pivot]);
    for (std::size_t i = k + 1; i < m; ++i) {
      const double factor = A[i * m + k] / A[k * m + k];
      for (std::size_t j = k; j < m; ++j) A[i * m + j] -= factor * A[k * m + j];
      b[i] -= factor * b[k];
    }
  }
  std::vector<double> x(m);
  for (std::size_t k = m; k-- > 0;) {
    double sum = b[k];
    for (std::size_t j = k + 1; j < m; ++j) sum -= A[k * m + j] * x[j];
    x[k] = sum / A[k * m + k];
  }
  return x;
}

struct CellKernel {
  const tm_kernel* kernel = nullptr;
  std::vector<int> nodes;
  std::vector<double> consts;
};

TEST(RefinedPatch, HookeStaticSolveIsExactForALinearField) {
  HierarchicalMesh hierarchy(distorted_beam());
  // Refine a quad and a triangle, then one of the new children: quad fans,
  // one- and two-edge green triangles and level-2 cells.
  hierarchy.refine(std::vector<int>{4, 12});  // of 6 quads and 12 triangles
  const auto levels = hierarchy.leaf_levels();
  hierarchy.refine(std::vector<int>{static_cast<int>(std::find(levels.begin(), levels.end(), 1) - levels.begin())});
  const Mesh& mesh = hierarchy.leaf_mesh();
  refinement_test::expect_valid_leaf_mesh(hierarchy, "refined patch");
  ASSERT_GT(hierarchy.leaves_per_level().size(), 2u);
  int transitions = 0;
  for (char transition : hierarchy.leaf_transitions()) transitions += transition;
  ASSERT_GT(transitions, 4);

  const double params[2] = {1e6, 0.25};
  const std::size_t n = 2 * static_cast<std::size_t>(mesh.node_count());
  std::vector<double> K(n * n, 0.0);
  std::vector<CellKernel> cells;
  for (const tensormass::ElementBlock& block : mesh.blocks) {
    const tm_kernel& kernel = tensormass::Registry::instance().get("hooke", block.element->name, "whole");
    for (int local = 0; local < block.count(); ++local) {
      CellKernel cell{&kernel, {}, std::vector<double>(static_cast<std::size_t>(kernel.consts))};
      std::vector<double> rest;
      for (int node : block.cell_nodes(local)) {
        cell.nodes.push_back(node);
        rest.insert(rest.end(), {position(mesh, node)[0], position(mesh, node)[1]});
      }
      ASSERT_EQ(kernel.precompute(rest.data(), params, cell.consts.data()), 0) << "inverted cell " << local;
      const std::vector<double> zero(static_cast<std::size_t>(kernel.dofs), 0.0);
      std::vector<double> Ke(static_cast<std::size_t>(kernel.dofs * kernel.dofs));
      kernel.hessian(zero.data(), cell.consts.data(), Ke.data());
      for (int i = 0; i < kernel.dofs; ++i)
        for (int j = 0; j < kernel.dofs; ++j) {
          const std::size_t row = 2 * static_cast<std::size_t>(cell.nodes[i / 2]) + i % 2;
          const std::size_t col = 2 * static_cast<std::size_t>(cell.nodes[j / 2]) + j % 2;
          K[row * n + col] += Ke[static_cast<std::size_t>(i * kernel.dofs + j)];
        }
      cells.push_back(std::move(cell));
    }
  }
  std::vector<double> u(n, 0.0), expected(n);
  std::vector<std::size_t> inner;
  for (int node = 0; node < mesh.node_count(); ++node) {
    const double* x = position(mesh, node);
    const bool boundary = x[0] == 0 || x[0] == 6 || x[1] == 0 || x[1] == 3;
    for (int c = 0; c < 2; ++c) {
      const std::size_t dof = 2 * static_cast<std::size_t>(node) + c;
      expected[dof] = exact(x, c);
      if (boundary) u[dof] = expected[dof];
      else inner.push_back(dof);
    }
  }
  const std::size_t m = inner.size();
  ASSERT_GT(m, 40u);
  std::vector<double> A(m * m), b(m, 0.0);
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = 0; j < n; ++j) b[i] -= K[inner[i] * n + j] * u[j];
    for (std::size_t j = 0; j < m; ++j) A[i * m + j] = K[inner[i] * n + inner[j]];
  }
  const std::vector<double> solution = solve_dense(A, b);
  for (std::size_t i = 0; i < m; ++i) u[inner[i]] = solution[i];
  for (std::size_t dof = 0; dof < n; ++dof) EXPECT_NEAR(u[dof], expected[dof], 1e-12) << "dof " << dof;
  // Plane strain, E = 1e6, nu = 0.25: sigma_x = sigma_y = 1600, tau_xy = 400.
  const double stress[4] = {1600, 400, 400, 1600};
  for (std::size_t e = 0; e < cells.size(); ++e) {
    const tm_kernel& kernel = *cells[e].kernel;
    std::vector<double> ue;
    for (int node : cells[e].nodes) ue.insert(ue.end(), {u[2 * node], u[2 * node + 1]});
    std::vector<double> P(static_cast<std::size_t>(kernel.quadrature_points * 4));
    kernel.stress(ue.data(), cells[e].consts.data(), P.data());
    for (std::size_t k = 0; k < P.size(); ++k) EXPECT_NEAR(P[k], stress[k % 4], 1e-6) << "cell " << e;
  }
}

}  // namespace
