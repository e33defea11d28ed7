// Jacobi-preconditioned conjugate gradients, warm-started.
#include <cmath>
#include <vector>

#include "linear_solvers/preconditioned_cg.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"

namespace tensormass {

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

std::unique_ptr<LinearSolver> make_cg_solver(const LinearSolverSettings& settings) {
  return std::make_unique<ConjugateGradientSolver>(settings);
}

}  // namespace tensormass
