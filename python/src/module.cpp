// The compiled part of the `tensormass` Python package (_tensormass); the
// package's __init__.py re-exports it.
#include <pybind11/pybind11.h>

#include "kernel_bindings.hpp"
#include "simulation_bindings.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/common/version.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/parallel/mpi_world.hpp"

PYBIND11_MODULE(_tensormass, m) {
  m.doc() = "tensormass: adaptive Tensor-Mass soft-tissue simulation (compiled core)";
  m.attr("__version__") = tensormass::kVersion;
  // Input errors (file, line, key) are Python ValueErrors, failed writes
  // OSErrors; numerical failures get their own type, a RuntimeError.
  pybind11::register_exception<tensormass::NumericalError>(m, "NumericalError", PyExc_RuntimeError);
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const tensormass::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const tensormass::OutputError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    }
  });
  tensormass::python::bind_kernels(m);
  tensormass::python::bind_simulation(m);
  // Under mpirun every rank imports this module: MPI starts here, and ends
  // when the interpreter exits. Elsewhere neither does anything.
  tensormass::parallel::start_world();
  pybind11::module_::import("atexit").attr("register")(
      pybind11::cpp_function([] { tensormass::parallel::finish_world(); }));
  m.def("mpi_rank", &tensormass::parallel::world_rank, "This process's MPI rank (0 unless run by mpirun).");
  m.def("mpi_size", &tensormass::parallel::world_size, "The number of MPI ranks (1 unless run by mpirun).");
  m.def("petsc_available", &tensormass::petsc_available,
        "Whether this build has PETSc (solver.backend: petsc, runs over MPI ranks).");
}
