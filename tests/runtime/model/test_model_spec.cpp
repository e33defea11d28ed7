// The model specification (tensormass/model/model_spec.hpp): the elastic
// constants are exactly the parameters of every law said to take Young's
// modulus and Poisson's ratio, and a default spec constrains, rotates and
// ramps nothing. (Time profiles: test_time_profile.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "tensormass/kernels/law_parameters.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/model/model_spec.hpp"

namespace tensormass {
namespace {

TEST(ModelSpec, ElasticConstantsAreYoungAndPoisson) {
  EXPECT_EQ(elastic_constants(2.5e6, 0.45), (std::map<std::string, double>{{"poisson", 0.45}, {"young", 2.5e6}}));
}

TEST(ModelSpec, ElasticConstantsAreAllTheParametersOfTheElasticLaws) {
  for (const char* law : {"hooke", "stvk", "neohookean", "corotational", "stable_neohookean"}) {
    const tm_kernel* kernel = Registry::instance().law_kernel(law);
    ASSERT_NE(kernel, nullptr) << law;
    std::vector<std::string> names = parameter_names(*kernel);
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"poisson", "young"})) << law;
  }
}

TEST(ModelSpec, ADefaultSpecConstrainsRotatesAndLoadsNothing) {
  const MaterialSpec material;
  EXPECT_EQ(material.region, "all");
  EXPECT_EQ(material.split, "");
  EXPECT_EQ(material.density, 0);
  const PrescribedSpec prescribed;
  EXPECT_EQ(prescribed.components, (std::array<bool, 3>{true, true, true}));
  EXPECT_EQ(prescribed.displacement, (std::array<double, 3>{0, 0, 0}));
  EXPECT_FALSE(prescribed.rotates);
  EXPECT_EQ(prescribed.rotation.axis, (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(prescribed.rotation.angle, 0);
  EXPECT_EQ(prescribed.profile.kind, ProfileKind::constant);
  for (double t : {-1.0, 0.0, 0.5, 3.0}) EXPECT_EQ(prescribed.profile.factor(t), 1.0);
  const LoadsSpec loads;
  EXPECT_EQ(loads.gravity, (std::array<double, 3>{0, 0, 0}));
  EXPECT_TRUE(loads.nodal_forces.empty());
  EXPECT_TRUE(loads.pressures.empty());
  EXPECT_EQ(loads.profile.kind, ProfileKind::constant);
}

}  // namespace
}  // namespace tensormass
