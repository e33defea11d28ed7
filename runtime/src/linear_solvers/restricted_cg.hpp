// Conjugate gradients preconditioned by an old factor, run on the rows
// where the matrix changed since that factor (internal header).
#ifndef TENSORMASS_LINEAR_SOLVERS_RESTRICTED_CG_HPP
#define TENSORMASS_LINEAR_SOLVERS_RESTRICTED_CG_HPP

#include <span>
#include <vector>

#include "linear_solvers/factor_reach.hpp"
#include "linear_solvers/preconditioned_cg.hpp"
#include "tensormass/assembly/sparse_matrix.hpp"

namespace tensormass::detail {

/// D = A - F on the rows N where A's values differ from F's (the matrix
/// that was factorised; same pattern). A and F are symmetric, so every
/// entry of D lies between two rows of N.
struct ChangedBlock {
  std::vector<int> rows;       ///< N, ascending, A's numbering
  std::vector<int> start;      ///< rows.size() + 1, into columns and values
  std::vector<int> columns;    ///< positions in `rows`
  std::vector<double> values;  ///< D's entries
  /// q += D p, p and q indexed like `rows`.
  void multiply_add(std::span<const double> p, std::span<double> q) const;
};

/// The block where A's values differ from `factorized` (A's pattern).
ChangedBlock changed_block(const SparseMatrix& A, std::span<const double> factorized);

/// Vectors reused between solves: in the factor's order (n) or on N (m).
struct RestrictedWorkspace {
  std::vector<double> base, work;             // n
  std::vector<double> w, r, z, p, t, q, x_n;  // m
};

/// Solves A x = b, A = F + D (F = L L^T, D = `change`), by conjugate
/// gradients preconditioned by F from x0 = F^-1 (b + w0), w0 = -D x (x:
/// the caller's guess): the same iteration as preconditioned_cg from x0.
/// From there every residual is zero outside N, so each iteration needs
/// F^-1 r on N only: two substitutions over the supernodes N reaches
/// (`reach` must have selected change.rows). The iterate is kept as
/// x = F^-1 (b + w), w on N; x is formed once, at the end (one whole
/// substitution each way). Stops at |r| <= tolerance |b| or after
/// max_iterations (converged = false, x = the last iterate).
PcgResult restricted_cg(const FactorReach& reach, const ChangedBlock& change, std::span<const double> b,
                        std::span<double> x, double tolerance, int max_iterations, RestrictedWorkspace& ws);

}  // namespace tensormass::detail

#endif
