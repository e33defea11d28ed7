/// \file linear_solver.hpp
/// Solvers of K x = b for the symmetric matrices of assembly: sparse
/// Cholesky (SuiteSparse CHOLMOD, supernodal; simplicial LDL^T when K is
/// not positive definite) and Jacobi-preconditioned conjugate gradients
/// warm-started from the caller's x.
#ifndef TENSORMASS_LINEAR_SOLVER_HPP
#define TENSORMASS_LINEAR_SOLVER_HPP

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tensormass/assembly/sparse_matrix.hpp"
#include "tensormass/solvers/solver_settings.hpp"

namespace tensormass {

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  /// Prepares for matrices with A's pattern, then factorises A (direct
  /// solvers) or keeps A (iterative ones); A must outlive the solves. Throws NumericalError when A is singular.
  virtual void factorize(const SparseMatrix& A) = 0;
  /// Solves A x = b to the relative residual `tolerance` (iterative
  /// solves; a direct solve is exact); x holds the initial guess on entry
  /// (used by CG). Returns the iterations (1 for a direct solve). Throws
  /// NumericalError when CG does not reach the tolerance.
  virtual int solve(std::span<const double> b, std::span<double> x, double tolerance) = 0;
  virtual std::string name() const = 0;
  /// Numeric factorisations so far (0 for iterative solvers).
  virtual int factorizations() const { return 0; }
  /// What the solver keeps between solves, flat, for a checkpoint (a direct
  /// solver: the matrix its factor came from and its reuse counts); empty
  /// when it keeps nothing (CG: the caller holds its warm start).
  virtual std::vector<double> save_state() const { return {}; }
  /// Restores save_state()'s output, for matrices with `pattern`'s pattern:
  /// a direct solver factorises the saved matrix again, which gives the same
  /// factor bit for bit. Throws InputError when `saved` does not fit.
  virtual void restore_state(std::span<const double> saved, const SparseMatrix& pattern);
};

std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSettings& settings);

}  // namespace tensormass

#endif
