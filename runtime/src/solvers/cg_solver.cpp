// Jacobi-preconditioned conjugate gradients, warm-started.
#include <cmath>
#include <vector>

#include "solvers/preconditioned_cg.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/model/model.hpp"
#include "tensormass/solvers/linear_solver.hpp"

namespace tensormass {

std::unique_ptr<LinearSolver> make_cholmod_solver(const LinearSolverSettings& settings);
std::unique_ptr<LinearSolver> make_petsc_solver(const LinearSolverSettings& settings);

namespace {

constexpr int kParallelLength = 50000;  // smaller vectors: one thread is faster

class ConjugateGradientSolver final : public LinearSolver {
 public:
  explicit ConjugateGradientSolver(const LinearSolverSettings& settings) : settings_(settings) {}

  void factorize(const SparseMatrix& A) override {
    A_ = &A;
    inverse_diagonal_.resize(A.rows);
    for (int i = 0; i < A.rows; ++i) {
      const double diagonal = A.diagonal[i] >= 0 ? A.values[A.diagonal[i]] : 0.0;
      if (!(diagonal > 0.0))
        throw NumericalError("conjugate gradients: non-positive diagonal entry at free dof " + std::to_string(i));
      inverse_diagonal_[i] = 1.0 / diagonal;
    }
  }

  int solve(std::span<const double> b, std::span<double> x, double tolerance) override {
    const auto jacobi = [this](std::span<const double> r, std::span<double> z) {
      const int n = static_cast<int>(r.size());
#pragma omp parallel for schedule(static) if (n >= kParallelLength)
      for (int i = 0; i < n; ++i) z[i] = inverse_diagonal_[i] * r[i];
    };
    const detail::PcgResult result =
        detail::preconditioned_cg(*A_, b, x, jacobi, tolerance, settings_.max_iterations, workspace_);
    if (!result.converged)
      throw NumericalError("conjugate gradients did not converge in " + std::to_string(settings_.max_iterations) +
                           " iterations (relative residual " + std::to_string(result.relative_residual) + ")");
    return result.iterations;
  }

  std::string name() const override { return "cg (Jacobi)"; }

 private:
  LinearSolverSettings settings_;
  const SparseMatrix* A_ = nullptr;
  std::vector<double> inverse_diagonal_;
  detail::PcgWorkspace workspace_;
};

}  // namespace

void LinearSolver::restore_state(std::span<const double> saved, const SparseMatrix&) {
  if (!saved.empty())
    throw InputError("the checkpoint holds a direct solver's factor; this run's linear solver (" + name() +
                     ") keeps none");
}

void describe_free_nodes(LinearSolver& solver, const Model& model) {
  const int d = model.dim();
  const auto& free = model.free_dofs();
  if (free.size() % d != 0) return;
  std::vector<double> coordinates;
  coordinates.reserve(free.size());
  for (std::size_t block = 0; block < free.size(); block += d) {
    const int node = free[block] / d;
    for (int a = 0; a < d; ++a)
      if (free[block + a] != node * d + a) return;  // a node with only some components free
    for (int a = 0; a < d; ++a)
      coordinates.push_back(model.mesh().rest_positions[3 * static_cast<std::size_t>(node) + a]);
  }
  solver.set_node_blocks(d, coordinates);
}

std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSettings& settings) {
  if (settings.type == LinearSolverType::cg) return std::make_unique<ConjugateGradientSolver>(settings);
  if (settings.type == LinearSolverType::petsc) return make_petsc_solver(settings);
  return make_cholmod_solver(settings);
}

}  // namespace tensormass
