// Builds without PETSc: the scene refuses `linear.type: petsc` (scene.cpp),
// so this is reached only by code that skips the scene.
#include <stdexcept>

#include "tensormass/linear_solvers/linear_solver.hpp"

namespace tensormass {

bool petsc_available() { return false; }

std::unique_ptr<LinearSolver> make_petsc_solver(const LinearSolverSettings&) {
  throw std::invalid_argument("this build has no PETSc (configure with libpetsc-real-dev installed)");
}

}  // namespace tensormass
