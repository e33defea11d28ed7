/// \file locking_warning.hpp
/// First-order elements lock near incompressibility: at a Poisson's ratio
/// above 0.45 a mesh of tet4 (and, less, of hex8, prism6, pyramid5, tri3 or
/// quad4) answers too stiff, while the quadratic elements stay close to the
/// converged answer. A run says so before it starts, per material and
/// element type, rather than give a stiff answer without a word.
#ifndef TENSORMASS_MODEL_LOCKING_WARNING_HPP
#define TENSORMASS_MODEL_LOCKING_WARNING_HPP

#include <string>
#include <vector>

#include "tensormass/model/model.hpp"
#include "tensormass/model/model_spec.hpp"

namespace tensormass {

/// Poisson's ratios above this lock first-order elements.
inline constexpr double kLockingPoisson = 0.45;

/// One warning per (material, first-order element type) whose cells are
/// under a material with a `poisson` constant above kLockingPoisson, in the
/// order of the materials and then of the element names; none otherwise.
/// `spec`: the specification `model` was built from.
std::vector<std::string> locking_warnings(const Model& model, const ModelSpec& spec);

}  // namespace tensormass

#endif
