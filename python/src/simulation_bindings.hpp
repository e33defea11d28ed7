// Bindings of the stepping Simulation (internal header of the Python module).
#ifndef TENSORMASS_PYTHON_SIMULATION_BINDINGS_HPP
#define TENSORMASS_PYTHON_SIMULATION_BINDINGS_HPP

#include <pybind11/pybind11.h>

namespace tensormass::python {

/// Adds Simulation to the module.
void bind_simulation(pybind11::module_& m);

}  // namespace tensormass::python

#endif
