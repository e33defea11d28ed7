// tensormass.kernels() and tensormass.kernel(law, element, split): the
// registry's C ABI kernels on NumPy batches of elements (no Python loop).
#include "kernel_bindings.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "tensormass/kernels/law_parameters.hpp"
#include "tensormass/kernels/registry.hpp"

namespace py = pybind11;

namespace tensormass::python {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// One kernel applied to a batch: rest and u are (n, nodes, dim).
class BatchKernel {
 public:
  explicit BatchKernel(const tm_kernel& kernel) : kernel_(&kernel) {}

  const tm_kernel& kernel() const { return *kernel_; }

  Array energy(const Array& rest, const Array& u, const py::kwargs& params) const {
    const Batch batch = prepare(rest, u, params);
    Array out(std::vector<py::ssize_t>{batch.count});
    double* values = out.mutable_data();
    {
      py::gil_scoped_release release;
      for (py::ssize_t e = 0; e < batch.count; ++e) values[e] = kernel_->energy(batch.u(e), batch.consts(e));
    }
    return out;
  }

  Array gradient(const Array& rest, const Array& u, const py::kwargs& params) const {
    const Batch batch = prepare(rest, u, params);
    Array out(std::vector<py::ssize_t>{batch.count, kernel_->dofs});
    double* values = out.mutable_data();
    {
      py::gil_scoped_release release;
      for (py::ssize_t e = 0; e < batch.count; ++e)
        kernel_->gradient(batch.u(e), batch.consts(e), values + e * kernel_->dofs);
    }
    return out;
  }

  Array hessian(const Array& rest, const Array& u, const py::kwargs& params) const {
    const Batch batch = prepare(rest, u, params);
    const py::ssize_t dofs = kernel_->dofs;
    Array out(std::vector<py::ssize_t>{batch.count, dofs, dofs});
    double* values = out.mutable_data();
    {
      py::gil_scoped_release release;
      for (py::ssize_t e = 0; e < batch.count; ++e)
        kernel_->hessian(batch.u(e), batch.consts(e), values + e * dofs * dofs);
    }
    return out;
  }

 private:
  /// The batch's displacements and precomputed constants.
  struct Batch {
    py::ssize_t count = 0;
    int dofs = 0;
    const double* displacement = nullptr;
    std::vector<double> constants;
    int per_element = 0;
    const double* u(py::ssize_t e) const { return displacement + e * dofs; }
    const double* consts(py::ssize_t e) const { return constants.data() + e * per_element; }
  };

  /// Checks the shapes, reads the parameters by name and precomputes every
  /// element's constants (ValueError for a bad shape, a missing or unknown
  /// parameter, or an element with a non-positive rest Jacobian).
  Batch prepare(const Array& rest, const Array& u, const py::kwargs& params) const {
    const tm_kernel& k = *kernel_;
    check_shape(rest, "rest");
    check_shape(u, "u");
    if (rest.shape(0) != u.shape(0))
      throw py::value_error("rest and u hold " + std::to_string(rest.shape(0)) + " and " + std::to_string(u.shape(0)) +
                            " elements");
    const std::vector<double> values = parameters(params);
    Batch batch;
    batch.count = rest.shape(0);
    batch.dofs = k.dofs;
    batch.displacement = u.data();
    batch.per_element = k.consts;
    batch.constants.resize(static_cast<std::size_t>(batch.count) * k.consts);
    for (py::ssize_t e = 0; e < batch.count; ++e) {
      const int status = k.precompute(rest.data() + e * k.dofs, values.data(), static_cast<int>(values.size()),
                                      batch.constants.data() + e * k.consts);
      if (status != 0)
        throw py::value_error("element " + std::to_string(e) + ": non-positive rest Jacobian at quadrature point " +
                              std::to_string(status - 1));
    }
    return batch;
  }

  void check_shape(const Array& a, const char* name) const {
    const tm_kernel& k = *kernel_;
    if (a.ndim() != 3 || a.shape(1) != k.nodes || a.shape(2) != k.dim)
      throw py::value_error(std::string(name) + " must have shape (n, " + std::to_string(k.nodes) + ", " +
                            std::to_string(k.dim) + ") for " + k.element);
  }

  std::vector<double> parameters(const py::kwargs& given) const {
    const tm_kernel& k = *kernel_;
    std::vector<double> values(k.params);
    std::size_t used = 0;
    for (int p = 0; p < k.params; ++p) {
      const char* name = k.param_names[p];
      if (!given.contains(name)) throw py::value_error(std::string("missing parameter '") + name + "'");
      values[p] = given[name].cast<double>();
      if (!within_limit(values[p], k.param_limits[p]))
        throw py::value_error(std::string(name) + " must be " + describe_limit(k.param_limits[p]) + " for law " +
                              k.law + ", got " + py::str(given[name]).cast<std::string>());
      ++used;
    }
    if (used != given.size()) {
      for (const auto& item : given) {
        const std::string name = py::str(item.first);
        bool known = false;
        for (int p = 0; p < k.params; ++p) known = known || name == k.param_names[p];
        if (!known) throw py::value_error("unknown parameter '" + name + "' for law " + k.law);
      }
    }
    return values;
  }

  const tm_kernel* kernel_;
};

py::dict describe(const tm_kernel& k) {
  py::dict d;
  d["law"] = k.law, d["element"] = k.element, d["split"] = k.split;
  d["nodes"] = k.nodes, d["dim"] = k.dim, d["dofs"] = k.dofs;
  d["quadrature_points"] = k.quadrature_points;
  std::vector<std::string> names(k.param_names, k.param_names + k.params);
  d["parameters"] = names;
  py::list limits;
  for (int p = 0; p < k.params; ++p) limits.append(describe_limit(k.param_limits[p]));
  d["limits"] = limits;
  d["flops_energy"] = k.flops_energy, d["flops_gradient"] = k.flops_gradient, d["flops_hessian"] = k.flops_hessian;
  d["linear"] = k.linear != 0, d["invertible"] = k.invertible != 0;
  return d;
}

}  // namespace

void bind_kernels(py::module_& m) {
  py::class_<BatchKernel>(m, "Kernel",
                          "A generated kernel (law, element, split) applied to batches of elements.\n\n"
                          "Arrays: rest and u have shape (n, nodes, dim); parameters are keywords "
                          "(young=..., poisson=...).")
      .def_property_readonly("law", [](const BatchKernel& k) { return std::string(k.kernel().law); })
      .def_property_readonly("element", [](const BatchKernel& k) { return std::string(k.kernel().element); })
      .def_property_readonly("split", [](const BatchKernel& k) { return std::string(k.kernel().split); })
      .def_property_readonly("nodes", [](const BatchKernel& k) { return k.kernel().nodes; })
      .def_property_readonly("dim", [](const BatchKernel& k) { return k.kernel().dim; })
      .def_property_readonly("dofs", [](const BatchKernel& k) { return k.kernel().dofs; })
      .def(
          "info", [](const BatchKernel& k) { return describe(k.kernel()); }, "The kernel's facts as a dict.")
      .def("energy", &BatchKernel::energy, py::arg("rest"), py::arg("u"), "Strain energy of each element: shape (n,).")
      .def("gradient", &BatchKernel::gradient, py::arg("rest"), py::arg("u"),
           "Internal force dW/du of each element: shape (n, dofs), dofs node-major.")
      .def("hessian", &BatchKernel::hessian, py::arg("rest"), py::arg("u"),
           "Tangent d2W/du2 of each element: shape (n, dofs, dofs).")
      .def("__repr__", [](const BatchKernel& k) {
        return std::string("<tensormass.Kernel ") + k.kernel().law + "/" + k.kernel().element + "/" + k.kernel().split +
               ">";
      });
  m.def(
      "kernels",
      [] {
        py::list out;
        for (const tm_kernel* k : Registry::instance().kernels()) out.append(describe(*k));
        return out;
      },
      "Every kernel of the registry, as dicts (law, element, split, nodes, dim, dofs, parameters, flops_*, ...).");
  m.def(
      "kernel",
      [](const std::string& law, const std::string& element, const std::string& split) {
        const tm_kernel* k = Registry::instance().find(law, element, split);
        if (!k) throw py::value_error("no kernel " + law + "/" + element + "/" + split + " (see tensormass.kernels())");
        return BatchKernel(*k);
      },
      py::arg("law"), py::arg("element"), py::arg("split") = "whole", "The kernel of a (law, element, split) triple.");
}

}  // namespace tensormass::python
