#include "tensormass/integrators/solver_settings.hpp"

namespace tensormass {

std::string_view solver_type_name(SolverType type) {
  switch (type) {
    case SolverType::implicit_euler: return "implicit";
    case SolverType::explicit_euler: return "explicit";
    case SolverType::static_newton: break;
  }
  return "static";
}

std::string_view step_predictor_name(StepPredictor predictor) {
  return predictor == StepPredictor::none ? "none" : "velocity";
}

}  // namespace tensormass
