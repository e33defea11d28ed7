// PETSc started once per process (internal header; builds with PETSc).
#ifndef TENSORMASS_PARALLEL_PETSC_START_HPP
#define TENSORMASS_PARALLEL_PETSC_START_HPP

namespace tensormass::parallel::detail {

/// Starts PETSc (and MPI, as a singleton process unless mpirun launched
/// this one) on first use, with errors returned rather than printed. Throws
/// NumericalError when PETSc fails to start.
void ensure_petsc_started();

}  // namespace tensormass::parallel::detail

#endif
