// Patch test on refined meshes: a distorted mixed quad4/tri3 mesh and a
// distorted hex8/prism6 block, refined locally (children and transition
// cells), assembled from the Hooke kernels' stiffness (2D: plane strain). The boundary nodes carry an
// exact linear field, the inner ones are solved for: they must get the
// exact field and every cell the same constant stress. A refined mesh the
// kernels reject (an inverted cell) or a wrong transition fails it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
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

/// Strain 1e-3 ((2, 1, 1), (1, 2, 1), (1, 1, 2)) / 2 (2D: the upper-left
/// block): u = strain x.
double exact(const double* x, int c, int dim) {
  double sum = 0;
  for (int d = 0; d < dim; ++d) sum += (c == d ? 2.0 : 1.0) * x[d];
  return 1e-3 * sum / 2;
}

/// Assembles the Hooke stiffness of `mesh` (E 1e6, nu 0.25), puts the exact
/// field on the nodes for which `boundary` holds, solves for the others and
/// checks that every node has the exact field and every quadrature point
/// the stress `stress` (dim by dim).
void expect_patch_test_passes(const Mesh& mesh, int dim, bool (*boundary)(const double*),
                              const std::vector<double>& stress) {
  const double params[2] = {1e6, 0.25};
  const auto d = static_cast<std::size_t>(dim);
  const std::size_t n = d * static_cast<std::size_t>(mesh.node_count());
  std::vector<double> K(n * n, 0.0);
  std::vector<CellKernel> cells;
  for (const tensormass::ElementBlock& block : mesh.blocks) {
    const tm_kernel& kernel = tensormass::Registry::instance().get("hooke", block.element->name, "whole");
    for (int local = 0; local < block.count(); ++local) {
      CellKernel cell{&kernel, {}, std::vector<double>(static_cast<std::size_t>(kernel.consts))};
      std::vector<double> rest;
      for (int node : block.cell_nodes(local)) {
        cell.nodes.push_back(node);
        rest.insert(rest.end(), position(mesh, node), position(mesh, node) + dim);
      }
      ASSERT_EQ(kernel.precompute(rest.data(), params, 2, cell.consts.data()), 0)
          << "inverted " << block.element->name << " " << local;
      const std::vector<double> zero(static_cast<std::size_t>(kernel.dofs), 0.0);
      std::vector<double> Ke(static_cast<std::size_t>(kernel.dofs * kernel.dofs));
      kernel.hessian(zero.data(), cell.consts.data(), Ke.data());
      for (int i = 0; i < kernel.dofs; ++i)
        for (int j = 0; j < kernel.dofs; ++j) {
          const std::size_t row = d * static_cast<std::size_t>(cell.nodes[i / dim]) + i % dim;
          const std::size_t col = d * static_cast<std::size_t>(cell.nodes[j / dim]) + j % dim;
          K[row * n + col] += Ke[static_cast<std::size_t>(i * kernel.dofs + j)];
        }
      cells.push_back(std::move(cell));
    }
  }
  std::vector<double> u(n, 0.0), expected(n);
  std::vector<std::size_t> inner;
  for (int node = 0; node < mesh.node_count(); ++node) {
    const double* x = position(mesh, node);
    for (int c = 0; c < dim; ++c) {
      const std::size_t dof = d * static_cast<std::size_t>(node) + c;
      expected[dof] = exact(x, c, dim);
      if (boundary(x)) u[dof] = expected[dof];
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
  for (std::size_t e = 0; e < cells.size(); ++e) {
    const tm_kernel& kernel = *cells[e].kernel;
    std::vector<double> ue;
    for (int node : cells[e].nodes) ue.insert(ue.end(), u.begin() + d * node, u.begin() + d * (node + 1));
    std::vector<double> P(static_cast<std::size_t>(kernel.quadrature_points) * d * d);
    kernel.stress(ue.data(), cells[e].consts.data(), P.data());
    for (std::size_t k = 0; k < P.size(); ++k) EXPECT_NEAR(P[k], stress[k % (d * d)], 1e-6) << "cell " << e;
  }
}

TEST(RefinedPatch, HookeStaticSolveIsExactForALinearField) {
  HierarchicalMesh hierarchy(distorted_beam());
  // Refine a quad and a triangle, then one of the new children: quad fans,
  // one- and two-edge green triangles and level-2 cells.
  hierarchy.refine(std::vector<int>{4, 12});  // of 6 quads and 12 triangles
  const auto levels = hierarchy.leaf_levels();
  hierarchy.refine(std::vector<int>{static_cast<int>(std::find(levels.begin(), levels.end(), 1) - levels.begin())});
  refinement_test::expect_valid_leaf_mesh(hierarchy, "refined patch");
  ASSERT_GT(hierarchy.leaves_per_level().size(), 2u);
  int transitions = 0;
  for (char transition : hierarchy.leaf_transitions()) transitions += transition;
  ASSERT_GT(transitions, 4);
  // Plane strain, E = 1e6, nu = 0.25: sigma_x = sigma_y = 1600, tau_xy = 400.
  expect_patch_test_passes(hierarchy.leaf_mesh(), 2,
                           [](const double* x) { return x[0] == 0 || x[0] == 6 || x[1] == 0 || x[1] == 3; },
                           {1600, 400, 400, 1600});
}

/// A 3 x 2 x 2 block of hex8 (x < 1.5) and prism6 cells with its inner
/// nodes moved by up to 0.1.
Mesh distorted_block() {
  tensormass::BeamSpec spec;
  spec.dim = 3;
  spec.cells = {4, 2, 2};
  spec.size = {3.0, 2.0, 2.0};
  spec.phases = {{"hex8", 0.5}, {"prism6", 0.5}};
  Mesh mesh = tensormass::make_beam(spec);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> shift(-0.1, 0.1);
  for (int node = 0; node < mesh.node_count(); ++node) {
    double* x = &mesh.rest_positions[3 * node];
    if (x[0] > 0 && x[0] < 3 && x[1] > 0 && x[1] < 2 && x[2] > 0 && x[2] < 2)
      for (int c = 0; c < 3; ++c) x[c] += shift(random);
  }
  return mesh;
}

TEST(RefinedPatch, HookeStaticSolveIsExactForALinearFieldIn3d) {
  HierarchicalMesh hierarchy(distorted_block());
  // A hex and a prism, then a child: quarters, fans, red-green faces and
  // the tets and pyramids of the transitions, level 2 cells.
  hierarchy.refine(std::vector<int>{1, 10});
  const auto levels = hierarchy.leaf_levels();
  hierarchy.refine(std::vector<int>{static_cast<int>(std::find(levels.begin(), levels.end(), 1) - levels.begin())});
  ASSERT_GT(hierarchy.leaves_per_level().size(), 2u);
  const Mesh& mesh = hierarchy.leaf_mesh();
  std::vector<std::string> elements;
  for (const tensormass::ElementBlock& block : mesh.blocks) elements.emplace_back(block.element->name);
  EXPECT_EQ(elements, (std::vector<std::string>{"hex8", "prism6", "tet4", "pyramid5"}));
  // E = 1e6, nu = 0.25: lambda = mu = 4e5; strain diagonal 1e-3, shears 5e-4.
  // sigma = lambda tr(eps) I + 2 mu eps: 2000 on the diagonal, 400 off it.
  expect_patch_test_passes(
      mesh, 3,
      [](const double* x) { return x[0] == 0 || x[0] == 3 || x[1] == 0 || x[1] == 2 || x[2] == 0 || x[2] == 2; },
      {2000, 400, 400, 400, 2000, 400, 400, 400, 2000});
}

}  // namespace
