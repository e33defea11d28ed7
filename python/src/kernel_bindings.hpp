// Bindings of the kernel registry (internal header of the Python module).
#ifndef TENSORMASS_PYTHON_KERNEL_BINDINGS_HPP
#define TENSORMASS_PYTHON_KERNEL_BINDINGS_HPP

#include <pybind11/pybind11.h>

namespace tensormass::python {

/// Adds Kernel, kernels() and kernel() to the module.
void bind_kernels(pybind11::module_& m);

}  // namespace tensormass::python

#endif
