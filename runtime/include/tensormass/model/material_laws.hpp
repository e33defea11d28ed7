/// \file material_laws.hpp
/// A material's constants bound to the registry's laws: the parameter array
/// each law's kernels take (law_parameters.hpp), the leading constants
/// (`derived_params` doubles of consts) each law computes from them, and the
/// small-strain Young's modulus of the material's own law.
#ifndef TENSORMASS_MODEL_MATERIAL_LAWS_HPP
#define TENSORMASS_MODEL_MATERIAL_LAWS_HPP

#include <array>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "tensormass/kernels/kernel_abi.h"
#include "tensormass/model/model_spec.hpp"

namespace tensormass {

class MaterialLaws {
 public:
  /// Binds `material`'s constants to every law of the registry whose
  /// parameters they hold; InputError naming `owner` ("scene.yaml:12:
  /// material 0") when its own law's are missing or outside their limits.
  MaterialLaws(const MaterialSpec& material, std::string owner);

  /// The parameter array of `kernel`'s law (its `params` values in order);
  /// InputError naming the material and the missing constant when the
  /// material lacks one.
  const std::vector<double>& parameters(const tm_kernel& kernel) const;
  /// Whether laws `a` and `b` compute the same leading constants from this
  /// material, so that a cell switches between them keeping its constants.
  bool share_constants(std::string_view a, std::string_view b) const;
  /// The small-strain Young's modulus of the material's law: its `young`
  /// constant, else measured on its stress kernel (uniaxial strain of the
  /// reference element): a scale for energies and stresses.
  double modulus() const { return modulus_; }
  /// The small-strain Lame parameters (lam, mu) of the material's law:
  /// from its `young` and `poisson` constants, else measured as modulus().
  std::array<double, 2> lame() const { return lame_; }
  const std::string& owner() const { return owner_; }
  /// The material's fibre fields (first and second family).
  const std::array<FibreField, 2>& fibres() const { return fibres_; }

 private:
  struct Bound {
    std::vector<double> parameters;
    std::vector<double> leading_consts;
  };
  std::map<std::string, Bound, std::less<>> laws_;
  std::map<std::string, double> constants_;
  std::array<FibreField, 2> fibres_;
  std::string owner_;
  double modulus_ = 0;
  std::array<double, 2> lame_{};
};

}  // namespace tensormass

#endif
