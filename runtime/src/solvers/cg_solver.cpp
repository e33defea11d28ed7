// Jacobi-preconditioned conjugate gradients, warm-started.
#include <cmath>
#include <vector>

#include "tensormass/errors.hpp"
#include "tensormass/linear_solver.hpp"

namespace tensormass {

std::unique_ptr<LinearSolver> make_cholmod_solver();

namespace {

constexpr int kParallelLength = 50000;  // smaller vectors: one thread is faster

class ConjugateGradientSolver final : public LinearSolver {
 public:
  explicit ConjugateGradientSolver(const LinearSolverSpec& spec) : spec_(spec) {}

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

  int solve(std::span<const double> b, std::span<double> x) override {
    const int n = A_->rows;
    r_.resize(n), z_.resize(n), p_.resize(n), q_.resize(n);
    A_->multiply(x, r_);
#pragma omp parallel for schedule(static) if (n >= kParallelLength)
    for (int i = 0; i < n; ++i) r_[i] = b[i] - r_[i];
    const double b_norm = norm(b);
    if (b_norm == 0.0) {
      std::fill(x.begin(), x.end(), 0.0);
      return 0;
    }
    const double target = spec_.tolerance * b_norm;
    double residual = norm(r_);
    if (residual <= target) return 0;
    precondition();
    p_ = z_;
    double rz = dot(r_, z_);
    for (int iteration = 1; iteration <= spec_.max_iterations; ++iteration) {
      A_->multiply(p_, q_);
      const double alpha = rz / dot(p_, q_);
#pragma omp parallel for schedule(static) if (n >= kParallelLength)
      for (int i = 0; i < n; ++i) {
        x[i] += alpha * p_[i];
        r_[i] -= alpha * q_[i];
      }
      residual = norm(r_);
      if (!std::isfinite(residual)) throw NumericalError("conjugate gradients produced NaN (indefinite matrix?)");
      if (residual <= target) return iteration;
      precondition();
      const double rz_next = dot(r_, z_);
      const double beta = rz_next / rz;
      rz = rz_next;
#pragma omp parallel for schedule(static) if (n >= kParallelLength)
      for (int i = 0; i < n; ++i) p_[i] = z_[i] + beta * p_[i];
    }
    throw NumericalError("conjugate gradients did not converge in " + std::to_string(spec_.max_iterations) +
                         " iterations (relative residual " + std::to_string(residual / b_norm) + ")");
  }

  std::string name() const override { return "cg (Jacobi)"; }

 private:
  void precondition() {
    const int n = static_cast<int>(r_.size());
#pragma omp parallel for schedule(static) if (n >= kParallelLength)
    for (int i = 0; i < n; ++i) z_[i] = inverse_diagonal_[i] * r_[i];
  }

  LinearSolverSpec spec_;
  const SparseMatrix* A_ = nullptr;
  std::vector<double> inverse_diagonal_, r_, z_, p_, q_;
};

}  // namespace

std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSpec& spec) {
  if (spec.type == "cholmod") return make_cholmod_solver();
  if (spec.type == "cg") return std::make_unique<ConjugateGradientSolver>(spec);
  throw InputError("unknown linear solver type '" + spec.type + "' (known: cholmod, cg)");
}

}  // namespace tensormass
