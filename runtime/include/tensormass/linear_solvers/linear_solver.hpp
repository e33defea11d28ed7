/// \file linear_solver.hpp
/// Solvers of K x = b for the symmetric matrices of assembly: sparse
/// Cholesky (SuiteSparse CHOLMOD, supernodal; simplicial LDL^T when K is
/// not positive definite), Jacobi-preconditioned conjugate gradients
/// warm-started from the caller's x, and PETSc's Krylov solvers and
/// preconditioners (algebraic multigrid by default) when the build has PETSc.
#ifndef TENSORMASS_LINEAR_SOLVER_HPP
#define TENSORMASS_LINEAR_SOLVER_HPP

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tensormass/assembly/sparse_matrix.hpp"
#include "tensormass/linear_solvers/linear_solver_settings.hpp"

namespace tensormass {

class Distribution;

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
  /// Tells the solver that its unknowns are `dim` components of each of the
  /// nodes at `coordinates` (nodes by dim, rest positions), node-major: an
  /// algebraic multigrid preconditioner then builds its coarse spaces from
  /// the rigid-body modes. Ignored by the solvers that have no use for it.
  virtual void set_node_blocks(int /*dim*/, std::span<const double> /*coordinates*/) {}
  /// Shares the solve among MPI ranks (the distribution must outlive the
  /// solver). factorize() then gets this rank's partial assembly, whose own
  /// rows are complete (Distribution); b is read in this rank's rows, and x
  /// comes back complete on every rank (with a divided state,
  /// Distribution::divides_state: in this rank's rows). Throws InputError for the solvers
  /// that run on one process (all but PETSc's).
  virtual void distribute(const Distribution& distribution);
  /// The free dofs (sorted) whose rows and columns are the only ones that
  /// change between the matrices given to factorize(): those of the cells
  /// under a non-linear law (the others are folded into a constant part).
  /// `revision` changes whenever the set does. CHOLMOD uses it to correct
  /// its reused factor with an exact factor of that block. Ignored by the others.
  virtual void set_changing_rows(std::span<const int> /*rows*/, long /*revision*/) {}
  /// What the solver found wrong with its settings while solving (PETSc:
  /// options it never used), each said once; the caller takes them.
  virtual std::vector<std::string> take_warnings() { return {}; }
};

class Model;
/// Calls solver.set_node_blocks with the model's free nodes when every node
/// has all or none of its components free (the usual clamped or prescribed
/// groups); does nothing otherwise (a group held in some components only).
void describe_free_nodes(LinearSolver& solver, const Model& model);

std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSettings& settings);

/// Whether this build links PETSc (solver.linear.type: petsc).
bool petsc_available();

}  // namespace tensormass

#endif
