#include "tensormass/model/material_laws.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/law_parameters.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass {

namespace {

/// Whether `constants` has every parameter of `kernel`'s law.
bool has_parameters(const tm_kernel& kernel, const std::map<std::string, double>& constants) {
  for (int p = 0; p < kernel.params; ++p)
    if (!constants.contains(kernel.param_names[p]) && !is_fibre_parameter(kernel.param_names[p])) return false;
  return true;
}

/// consts of `kernel` on its reference element (rest positions = reference
/// nodes, so the rest Jacobian is the identity).
std::vector<double> reference_consts(const tm_kernel& kernel, const std::vector<double>& params,
                                     const std::string& owner) {
  const tm_element_info* element = Registry::instance().element(kernel.element);
  if (!element) throw std::logic_error(std::string("no reference element ") + kernel.element);
  std::vector<double> consts(static_cast<std::size_t>(kernel.consts));
  if (precompute_checked(kernel, element->reference_nodes, params, consts.data(), owner) != 0)
    throw std::logic_error(std::string("the reference ") + kernel.element + " has a non-positive Jacobian");
  return consts;
}

/// Young's modulus of the Lame parameters.
double young_of(const std::array<double, 2>& lame) {
  const auto [lam, mu] = lame;
  return mu * (3 * lam + 2 * mu) / (lam + mu);
}

/// lam and mu from the first Piola stress of F = I +- delta e0 e0^T at the
/// first quadrature point (central differences: P00' = lam + 2 mu, P11' = lam).
std::array<double, 2> measured_lame(const tm_kernel& kernel, const std::vector<double>& consts) {
  const tm_element_info& element = *Registry::instance().element(kernel.element);
  const int d = kernel.dim;
  const double delta = 1e-6;
  std::vector<double> u(static_cast<std::size_t>(kernel.dofs), 0.0);
  std::vector<double> plus(static_cast<std::size_t>(kernel.quadrature_points * d * d));
  std::vector<double> minus(plus.size());
  for (int sign : {1, -1}) {
    for (int j = 0; j < kernel.nodes; ++j)
      u[static_cast<std::size_t>(j * d)] = sign * delta * element.reference_nodes[j * d];
    kernel.stress(u.data(), consts.data(), sign > 0 ? plus.data() : minus.data());
  }
  const double axial = (plus[0] - minus[0]) / (2 * delta);
  const double lam = (plus[static_cast<std::size_t>(d + 1)] - minus[static_cast<std::size_t>(d + 1)]) / (2 * delta);
  return {lam, (axial - lam) / 2};
}

/// lam and mu of the laws' [derived] tables, in the generated kernels'
/// order of operations (the same doubles as their consts[0] and consts[1]).
std::array<double, 2> elastic_lame(double young, double poisson) {
  return {poisson * young / ((1.0 - 2.0 * poisson) * (poisson + 1.0)), young / (2.0 * poisson + 2.0)};
}

}  // namespace

MaterialLaws::MaterialLaws(const MaterialSpec& material, std::string owner)
    : constants_(material.constants), fibres_(material.fibres), owner_(std::move(owner)) {
  const Registry& registry = Registry::instance();
  const tm_kernel* own = registry.law_kernel(material.law);
  if (!own) throw std::invalid_argument(owner_ + ": unknown law '" + material.law + "'");
  parameter_array(*own, constants_, owner_);  // the own law's constants: present and within limits
  for (const std::string& law : registry.laws()) {
    const tm_kernel& kernel = *registry.law_kernel(law);
    if (!has_parameters(kernel, constants_)) continue;
    std::vector<double> params;
    try {
      params = parameter_array(kernel, constants_, owner_);
    } catch (const InputError&) {
      continue;  // outside that law's limits: the material cannot take it
    }
    std::vector<double> consts = reference_consts(kernel, params, owner_);
    if (law == material.law) {
      const auto young = constants_.find("young"), poisson = constants_.find("poisson");
      const bool elastic = young != constants_.end() && poisson != constants_.end();
      lame_ = elastic ? elastic_lame(young->second, poisson->second) : measured_lame(kernel, consts);
      modulus_ = elastic ? young->second : young_of(lame_);
    }
    consts.resize(static_cast<std::size_t>(kernel.derived_params));
    laws_.emplace(law, Bound{std::move(params), std::move(consts)});
  }
  if (!(modulus_ > 0) || !std::isfinite(modulus_))
    throw InputError(owner_ + ": law " + material.law + " gives a small-strain Young's modulus of " +
                     std::to_string(modulus_) + " with these constants (not a positive number)");
}

const std::vector<double>& MaterialLaws::parameters(const tm_kernel& kernel) const {
  const auto found = laws_.find(kernel.law);
  if (found == laws_.end()) {
    parameter_array(kernel, constants_, owner_);  // throws, naming the missing or bad constant
    throw std::logic_error(owner_ + ": no parameters bound for law " + kernel.law);
  }
  return found->second.parameters;
}

bool MaterialLaws::share_constants(std::string_view a, std::string_view b) const {
  const auto first = laws_.find(a), second = laws_.find(b);
  // The fibre directions among the leading constants differ cell by cell.
  const auto fibred = [](std::string_view law) {
    const tm_kernel* kernel = Registry::instance().law_kernel(law);
    return kernel && fibre_families(*kernel) > 0;
  };
  if (fibred(a) || fibred(b)) return false;
  return first != laws_.end() && second != laws_.end() && first->second.leading_consts == second->second.leading_consts;
}

}  // namespace tensormass
