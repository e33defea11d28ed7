#include <algorithm>
#include <cmath>
#include <numbers>

#include "tensormass/model/model_spec.hpp"

namespace tensormass {

std::string_view profile_kind_name(ProfileKind kind) {
  switch (kind) {
    case ProfileKind::ramp: return "ramp";
    case ProfileKind::sinusoid: return "sinusoid";
    case ProfileKind::constant: break;
  }
  return "constant";
}

double TimeProfile::factor(double t) const {
  if (kind == ProfileKind::ramp) {
    if (!(duration > 0)) return t >= 0 ? 1.0 : 0.0;
    return std::clamp(t / duration, 0.0, 1.0);
  }
  if (kind == ProfileKind::sinusoid) {
    if (!(period > 0)) return 1.0;
    return (1.0 - std::cos(2.0 * std::numbers::pi * (t + phase) / period)) / 2.0;
  }
  return 1.0;
}

}  // namespace tensormass
