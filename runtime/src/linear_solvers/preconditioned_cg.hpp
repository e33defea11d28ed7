// Preconditioned conjugate gradients shared by the Jacobi CG solver and the
// lagged-factor mode of the Cholesky solver (internal header).
#ifndef TENSORMASS_LINEAR_SOLVERS_PRECONDITIONED_CG_HPP
#define TENSORMASS_LINEAR_SOLVERS_PRECONDITIONED_CG_HPP

#include <cmath>
#include <span>
#include <vector>

#include "tensormass/assembly/sparse_matrix.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::detail {

struct PcgResult {
  int iterations = 0;
  bool converged = false;
  double relative_residual = 0;
};

/// Vectors reused between solves.
struct PcgWorkspace {
  std::vector<double> r, z, p, q;
};

/// Solves A x = b from the initial guess in x; `precondition(r, z)` applies
/// z = M^-1 r. Stops at |r| <= tolerance |b| or after max_iterations
/// (converged = false, x = the last iterate). Throws NumericalError on NaN.
template <class Precondition>
PcgResult preconditioned_cg(const SparseMatrix& A, std::span<const double> b, std::span<double> x,
                            Precondition&& precondition, double tolerance, int max_iterations, PcgWorkspace& w) {
  constexpr int kParallelLength = 50000;  // smaller vectors: one thread is faster
  const int n = A.rows;
  w.r.resize(n), w.z.resize(n), w.p.resize(n), w.q.resize(n);
  A.multiply(x, w.r);
#pragma omp parallel for schedule(static) if (n >= kParallelLength)
  for (int i = 0; i < n; ++i) w.r[i] = b[i] - w.r[i];
  const double b_norm = norm(b);
  if (b_norm == 0.0) {
    for (double& value : x) value = 0.0;
    return {0, true, 0.0};
  }
  double residual = norm(w.r);
  if (residual <= tolerance * b_norm) return {0, true, residual / b_norm};
  precondition(std::span<const double>(w.r), std::span<double>(w.z));
  w.p = w.z;
  double rz = dot(w.r, w.z);
  for (int iteration = 1; iteration <= max_iterations; ++iteration) {
    A.multiply(w.p, w.q);
    const double alpha = rz / dot(w.p, w.q);
#pragma omp parallel for schedule(static) if (n >= kParallelLength)
    for (int i = 0; i < n; ++i) {
      x[i] += alpha * w.p[i];
      w.r[i] -= alpha * w.q[i];
    }
    residual = norm(w.r);
    if (!std::isfinite(residual)) throw NumericalError("conjugate gradients produced NaN (indefinite matrix?)");
    if (residual <= tolerance * b_norm) return {iteration, true, residual / b_norm};
    precondition(std::span<const double>(w.r), std::span<double>(w.z));
    const double rz_next = dot(w.r, w.z);
    const double beta = rz_next / rz;
    rz = rz_next;
#pragma omp parallel for schedule(static) if (n >= kParallelLength)
    for (int i = 0; i < n; ++i) w.p[i] = w.z[i] + beta * w.p[i];
  }
  return {max_iterations, false, residual / b_norm};
}

}  // namespace tensormass::detail

#endif
