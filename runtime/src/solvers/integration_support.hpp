// Helpers shared by the integrators (internal header).
#ifndef TENSORMASS_SOLVERS_INTEGRATION_SUPPORT_HPP
#define TENSORMASS_SOLVERS_INTEGRATION_SUPPORT_HPP

#include <chrono>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "tensormass/errors.hpp"
#include "tensormass/integrators.hpp"

namespace tensormass::detail {

/// Adds the wall time of its lifetime to `seconds`.
class PhaseTimer {
 public:
  explicit PhaseTimer(double& seconds) : seconds_(seconds), start_(std::chrono::steady_clock::now()) {}
  ~PhaseTimer() { seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

 private:
  double& seconds_;
  std::chrono::steady_clock::time_point start_;
};

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Assembles g(u) (and K when given), timed as assembly.
inline void assemble(Integration& run, std::span<const double> u, std::span<double> g, SparseMatrix* K) {
  PhaseTimer timer(run.statistics.assembly_seconds);
  run.assembler.assemble(u, g, K);
}

/// Factorises A and solves A x = b (x: initial guess in, solution out), timed as solve.
inline void linear_solve(Integration& run, const SparseMatrix& A, std::span<const double> b, std::span<double> x) {
  PhaseTimer timer(run.statistics.solve_seconds);
  run.linear.factorize(A);
  run.statistics.linear_iterations += run.linear.solve(b, x);
}

inline double max_abs(std::span<const double> v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

/// Throws NumericalError when a value is NaN or infinite.
inline void require_finite(std::span<const double> values, const std::string& what) {
  for (double x : values)
    if (!std::isfinite(x)) throw NumericalError(what + " is not finite (NaN or infinity)");
}

/// Throws NumericalError naming the first inverted element.
inline void require_no_inversion(const Model& model, std::span<const double> u, const std::string& where) {
  const int cell = model.first_inverted_cell(u);
  if (cell >= 0)
    throw NumericalError(model.mesh().describe_cell(cell) + " inverted (det F <= 0) " + where);
}

}  // namespace tensormass::detail

#endif
