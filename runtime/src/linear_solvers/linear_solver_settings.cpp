#include "tensormass/linear_solvers/linear_solver_settings.hpp"

namespace tensormass {

std::string_view linear_solver_type_name(LinearSolverType type) {
  switch (type) {
    case LinearSolverType::cg: return "cg";
    case LinearSolverType::petsc: return "petsc";
    case LinearSolverType::cholmod: break;
  }
  return "cholmod";
}

}  // namespace tensormass
