#include "tensormass/model/model_spec.hpp"

namespace tensormass {

std::map<std::string, double> elastic_constants(double young, double poisson) {
  return {{"young", young}, {"poisson", poisson}};
}

}  // namespace tensormass
