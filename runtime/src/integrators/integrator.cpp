#include <stdexcept>

#include "integrators/integrator_kinds.hpp"

namespace tensormass {

void Integrator::run(State& state, const StepObserver& observer) {
  while (!finished(state)) step(state, observer);
  finish(state);
}

std::unique_ptr<Integrator> make_integrator(Integration& run) {
  switch (run.settings.type) {
    case SolverType::static_newton: return std::make_unique<StaticIntegrator>(run);
    case SolverType::implicit_euler: return std::make_unique<ImplicitIntegrator>(run);
    case SolverType::explicit_euler: return std::make_unique<ExplicitIntegrator>(run);
  }
  throw std::invalid_argument("make_integrator: unknown solver type");
}

}  // namespace tensormass
