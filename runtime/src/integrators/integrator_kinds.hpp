// The three integrators behind make_integrator (internal header): each
// keeps the vectors and matrices its steps reuse.
#ifndef TENSORMASS_INTEGRATORS_INTEGRATOR_KINDS_HPP
#define TENSORMASS_INTEGRATORS_INTEGRATOR_KINDS_HPP

#include <utility>
#include <vector>

#include "tensormass/integrators/integrators.hpp"

namespace tensormass {

/// Static Newton, one load step per step (static_solver.cpp).
class StaticIntegrator final : public Integrator {
 public:
  using Integrator::Integrator;
  void step(State& state, const StepObserver& observer) override;
};

/// Backward Euler with Newton iterations and a line search (implicit_solver.cpp).
class ImplicitIntegrator final : public Integrator {
 public:
  explicit ImplicitIntegrator(Integration& run);
  void step(State& state, const StepObserver& observer) override;

 private:
  SparseMatrix K_, J_;             ///< tangent and step matrix (J_ empty without stiffness damping: J is formed in K_)
  std::vector<double> g_, v_, r_;  ///< internal force, velocity (dof_count), residual (free)
};

/// Symplectic Euler on the lumped mass (explicit_solver.cpp).
class ExplicitIntegrator final : public Integrator {
 public:
  /// Estimates the stable time step and warns when dt exceeds it.
  explicit ExplicitIntegrator(Integration& run);
  void step(State& state, const StepObserver& observer) override;
  void finish(const State& state) override;

 private:
  /// Advances v and u on the free dofs; returns whether every new u is finite.
  bool advance_free_dofs(State& state, double load_factor) const;

  std::vector<double> g_;  ///< internal force (dof_count)
  /// The free dofs as ranges [first, last) of consecutive dof indices, so
  /// that the step's vector update runs over contiguous memory.
  std::vector<std::pair<int, int>> free_ranges_;
};

}  // namespace tensormass

#endif
