/// \file law_parameters.hpp
/// A law's parameters as its kernels declare them (`param_names` and
/// `param_limits` of the C ABI, from the law file's `parameters` and
/// `limits`): the checks of given values and the array a kernel's
/// `precompute` takes. The runtime passes a kernel only arrays built here,
/// of exactly its `params` values in its order.
#ifndef TENSORMASS_KERNELS_LAW_PARAMETERS_HPP
#define TENSORMASS_KERNELS_LAW_PARAMETERS_HPP

#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tensormass/kernels/kernel_abi.h"

namespace tensormass {

/// The names of `kernel`'s parameters, in kernel order.
std::vector<std::string> parameter_names(const tm_kernel& kernel);

/// The limit as a message reads it: "> 0", "> -1 and < 0.5", "finite".
std::string describe_limit(const tm_param_limit& limit);

/// Whether `value` is finite and within `limit`.
bool within_limit(double value, const tm_param_limit& limit);

/// The kernel's parameter array, its parameters looked up by name in
/// `constants`. Throws InputError naming `owner` (e.g. "scene.yaml:
/// materials[0]"), the law and the missing constant, or the constant
/// outside its limits. Fibre directions (is_fibre_parameter) absent from
/// `constants` take placeholders, (1, 0, 0) and (0, 1, 0), that the model
/// replaces cell by cell.
std::vector<double> parameter_array(const tm_kernel& kernel, const std::map<std::string, double>& constants,
                                    const std::string& owner);

/// Values within every limit of the kernel's law: the middle of a two-sided
/// limit, 1 past a one-sided one, else 1. For evaluations that need some
/// admissible material (rest volumes, demonstrations), never for results.
std::vector<double> admissible_parameters(const tm_kernel& kernel);

/// The fibre families (0, 1 or 2) a law with fibre invariants reads: its
/// last 3 (or 6) parameters are their directions, fibre_x fibre_y fibre_z
/// then fibre2_x fibre2_y fibre2_z, which the model sets per cell.
int fibre_families(const tm_kernel& kernel);
/// Whether `name` is one of those direction parameters (not a material constant).
bool is_fibre_parameter(std::string_view name);

/// `kernel.precompute` with the parameter count passed through the C ABI.
/// Returns 0, or q+1 for a non-positive rest Jacobian at quadrature point q;
/// throws InputError naming `owner` when the kernel refuses the parameters
/// (a count other than its `params`, or a value outside its limits).
int precompute_checked(const tm_kernel& kernel, const double* rest_positions, std::span<const double> params,
                       double* consts, const std::string& owner);

}  // namespace tensormass

#endif
