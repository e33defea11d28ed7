#include "tensormass/kernels/law_parameters.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "tensormass/common/errors.hpp"

namespace tensormass {

namespace {

std::string number(double x) {
  std::ostringstream out;
  out.precision(17);
  out << x;
  return out.str();
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

}  // namespace

std::vector<std::string> parameter_names(const tm_kernel& kernel) {
  return {kernel.param_names, kernel.param_names + kernel.params};
}

std::string describe_limit(const tm_param_limit& limit) {
  std::string out;
  if (std::isfinite(limit.lower)) out = (limit.lower_inclusive ? ">= " : "> ") + number(limit.lower);
  if (std::isfinite(limit.upper))
    out += (out.empty() ? "" : " and ") + std::string(limit.upper_inclusive ? "<= " : "< ") + number(limit.upper);
  return out.empty() ? "finite" : out;
}

bool within_limit(double value, const tm_param_limit& limit) {
  if (!std::isfinite(value)) return false;
  const bool above = limit.lower_inclusive ? value >= limit.lower : value > limit.lower;
  const bool below = limit.upper_inclusive ? value <= limit.upper : value < limit.upper;
  return above && below;
}

std::vector<double> parameter_array(const tm_kernel& kernel, const std::map<std::string, double>& constants,
                                    const std::string& owner) {
  std::vector<double> values;
  values.reserve(static_cast<std::size_t>(kernel.params));
  for (int p = 0; p < kernel.params; ++p) {
    const auto found = constants.find(kernel.param_names[p]);
    if (found == constants.end() && is_fibre_parameter(kernel.param_names[p])) {
      const std::string_view name = kernel.param_names[p];
      const bool second = name.starts_with("fibre2_");
      values.push_back(name.ends_with(second ? "y" : "x") ? 1.0 : 0.0);
      continue;
    }
    if (found == constants.end())
      throw InputError(owner + ": law " + kernel.law + " needs the constant '" + kernel.param_names[p] +
                       "' (its parameters: " + joined(parameter_names(kernel)) + ")");
    if (!within_limit(found->second, kernel.param_limits[p]))
      throw InputError(owner + ": " + kernel.param_names[p] + " must be " + describe_limit(kernel.param_limits[p]) +
                       " for law " + kernel.law + ", got " + number(found->second));
    values.push_back(found->second);
  }
  return values;
}

std::vector<double> admissible_parameters(const tm_kernel& kernel) {
  std::vector<double> values;
  for (int p = 0; p < kernel.params; ++p) {
    const tm_param_limit& limit = kernel.param_limits[p];
    const bool low = std::isfinite(limit.lower), high = std::isfinite(limit.upper);
    values.push_back(low && high ? (limit.lower + limit.upper) / 2
                     : low       ? limit.lower + 1
                     : high      ? limit.upper - 1
                                 : 1.0);
  }
  return values;
}

bool is_fibre_parameter(std::string_view name) { return name.starts_with("fibre_") || name.starts_with("fibre2_"); }

int fibre_families(const tm_kernel& kernel) {
  int families = 0;
  for (int p = 0; p < kernel.params; ++p) {
    const std::string_view name = kernel.param_names[p];
    if (name == "fibre_x") families = std::max(families, 1);
    if (name == "fibre2_x") families = 2;
  }
  return families;
}

int precompute_checked(const tm_kernel& kernel, const double* rest_positions, std::span<const double> params,
                       double* consts, const std::string& owner) {
  const int status = kernel.precompute(rest_positions, params.data(), static_cast<int>(params.size()), consts);
  if (status == TM_PRECOMPUTE_PARAM_COUNT)
    throw InputError(owner + ": law " + kernel.law + " takes " + std::to_string(kernel.params) + " parameters (" +
                     joined(parameter_names(kernel)) + "), given " + std::to_string(params.size()));
  if (status <= TM_PRECOMPUTE_BAD_PARAM) {
    const int p = TM_PRECOMPUTE_BAD_PARAM - status;
    const std::string value = p < static_cast<int>(params.size()) ? number(params[p]) : "?";
    throw InputError(owner + ": " + (p < kernel.params ? kernel.param_names[p] : "a parameter") + " must be " +
                     (p < kernel.params ? describe_limit(kernel.param_limits[p]) : "within its limits") + " for law " +
                     kernel.law + ", got " + value);
  }
  return status;
}

}  // namespace tensormass
