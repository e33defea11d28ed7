#include <algorithm>
#include <cmath>
#include <numbers>

#include "tensormass/scene/scene.hpp"

namespace tensormass {

double TimeProfile::factor(double t) const {
  if (kind == "ramp") {
    if (!(duration > 0)) return t >= 0 ? 1.0 : 0.0;
    return std::clamp(t / duration, 0.0, 1.0);
  }
  if (kind == "sinusoid") {
    if (!(period > 0)) return 1.0;
    return (1.0 - std::cos(2.0 * std::numbers::pi * (t + phase) / period)) / 2.0;
  }
  return 1.0;
}

}  // namespace tensormass
