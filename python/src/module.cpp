// The compiled part of the `tensormass` Python package (_tensormass); the
// package's __init__.py re-exports it.
#include <pybind11/pybind11.h>

#include "kernel_bindings.hpp"
#include "simulation_bindings.hpp"
#include "tensormass/common/errors.hpp"

PYBIND11_MODULE(_tensormass, m) {
  m.doc() = "tensormass: adaptive Tensor-Mass soft-tissue simulation (compiled core)";
  // Input errors (file, line, key) are Python ValueErrors; numerical
  // failures get their own type, a RuntimeError.
  pybind11::register_exception<tensormass::NumericalError>(m, "NumericalError", PyExc_RuntimeError);
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const tensormass::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  tensormass::python::bind_kernels(m);
  tensormass::python::bind_simulation(m);
}
