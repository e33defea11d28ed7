// When a sparse Cholesky factor is computed afresh rather than reused as a
// CG preconditioner for a matrix that has drifted since (internal header).
#ifndef TENSORMASS_LINEAR_SOLVERS_FACTOR_REUSE_POLICY_HPP
#define TENSORMASS_LINEAR_SOLVERS_FACTOR_REUSE_POLICY_HPP

#include <array>

namespace tensormass::detail {

/// Costs are counted in solves with the factor (one forward and backward
/// substitution; a CG iteration preconditioned by the factor costs about
/// one). A cycle starts at a factorisation and ends at the next; the policy
/// keeps the mean cost per solve over the cycle low: it asks for a new
/// factor as soon as a solve costs more than that mean (the mean is then
/// rising). The counts, not clocks, decide, so runs repeat bitwise.
class FactorReusePolicy {
 public:
  /// One numeric factorisation in solve units: cholmod_factorize timed
  /// against cholmod_solve on the beams of bench runtime gave 25 (600
  /// quads) to 60 (1,200 tets), 33 at 15k tets and 38 at 100k (AMD EPYC,
  /// OpenBLAS, one thread).
  static constexpr double kFactorizationCost = 35.0;

  explicit FactorReusePolicy(double factorization_cost = kFactorizationCost)
      : factorization_cost_(factorization_cost) {}

  /// A new factor and its direct solve.
  void factorized() {
    cycle_cost_ = factorization_cost_ + 1.0;
    cycle_solves_ = 1;
    refactorize_ = false;
  }
  /// A solve with the old factor that cost `cost` solves (CG iterations
  /// preconditioned by it; fewer when they run on the changed rows only).
  void lagged_solve(double cost) {
    cycle_cost_ += cost;
    ++cycle_solves_;
    refactorize_ = cost > cycle_cost_ / cycle_solves_;
  }
  /// Whether the next changed matrix should be factorised afresh.
  bool refactorize() const { return refactorize_; }
  /// The counts of the current cycle, and back (checkpoints).
  std::array<double, 3> saved() const { return {cycle_cost_, double(cycle_solves_), refactorize_ ? 1.0 : 0.0}; }
  void restore(const std::array<double, 3>& saved) {
    cycle_cost_ = saved[0];
    cycle_solves_ = static_cast<int>(saved[1]);
    refactorize_ = saved[2] != 0.0;
  }

 private:
  double factorization_cost_;
  double cycle_cost_ = 0.0;
  int cycle_solves_ = 0;
  bool refactorize_ = false;
};

}  // namespace tensormass::detail

#endif
