// A material's constants bound to the registry's laws: parameter arrays,
// shared leading constants, the small-strain moduli, and the errors.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/model/material_laws.hpp"

namespace tensormass {
namespace {

MaterialSpec material(const std::string& law, std::map<std::string, double> constants) {
  MaterialSpec m;
  m.law = law;
  m.constants = std::move(constants);
  m.density = 1000;
  return m;
}

/// The first doubles `precompute` writes for (law, tet4, whole) on the reference tet4.
std::vector<double> leading_consts(const std::string& law, const std::vector<double>& params) {
  const tm_kernel& kernel = Registry::instance().get(law, "tet4", "whole");
  std::vector<double> consts(static_cast<std::size_t>(kernel.consts));
  EXPECT_EQ(kernel.precompute(Registry::instance().element("tet4")->reference_nodes, params.data(),
                              static_cast<int>(params.size()), consts.data()),
            0);
  consts.resize(static_cast<std::size_t>(kernel.derived_params));
  return consts;
}

TEST(MaterialLaws, ElasticConstantsGiveYoungAndTheKernelsLame) {
  const MaterialLaws laws(material("stvk", elastic_constants(2.5e5, 0.4)), "scene.yaml:3: material 0");
  EXPECT_EQ(laws.modulus(), 2.5e5);
  const auto [lam, mu] = laws.lame();
  EXPECT_EQ((std::vector<double>{lam, mu}), leading_consts("stvk", {2.5e5, 0.4})) << "bit for bit";
  const tm_kernel& hooke = Registry::instance().get("hooke", "hex8", "whole");
  EXPECT_EQ(laws.parameters(hooke), (std::vector<double>{2.5e5, 0.4}));
  EXPECT_TRUE(laws.share_constants("hooke", "stvk"));
  EXPECT_TRUE(laws.share_constants("hooke", "neohookean"));
  EXPECT_FALSE(laws.share_constants("hooke", "mooney_rivlin")) << "the material has no c10";
}

/// Small strains of Mooney-Rivlin: mu = 2 (c10 + c01), bulk modulus kappa,
/// so lam = kappa - 2 mu / 3 and E = 9 kappa mu / (3 kappa + mu).
TEST(MaterialLaws, OtherLawsGiveTheMeasuredSmallStrainModuli) {
  const double c10 = 1.6e5, c01 = 3.0e4, kappa = 2.0e6;
  const MaterialLaws laws(material("mooney_rivlin", {{"kappa", kappa}, {"c01", c01}, {"c10", c10}}), "material 0");
  const double mu = 2 * (c10 + c01);
  EXPECT_NEAR(laws.lame()[1], mu, 1e-7 * mu);
  EXPECT_NEAR(laws.lame()[0], kappa - 2 * mu / 3, 1e-7 * kappa);
  EXPECT_NEAR(laws.modulus(), 9 * kappa * mu / (3 * kappa + mu), 1e-7 * mu);
  const tm_kernel& kernel = Registry::instance().get("mooney_rivlin", "tet4", "whole");
  EXPECT_EQ(laws.parameters(kernel), (std::vector<double>{c10, c01, kappa})) << "in the kernel's order";
}

TEST(MaterialLaws, MissingOrBadConstantsNameTheMaterialLawAndConstant) {
  try {
    MaterialLaws(material("mooney_rivlin", {{"c10", 1.0}, {"c01", 1.0}}), "scene.yaml:4: material 1");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(),
                 "scene.yaml:4: material 1: law mooney_rivlin needs the constant 'kappa' (its parameters: c10, c01, "
                 "kappa)");
  }
  try {
    MaterialLaws(material("hooke", elastic_constants(1e6, 0.5)), "material 0");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "material 0: poisson must be > -1 and < 0.5 for law hooke, got 0.5");
  }
  const MaterialLaws laws(material("hooke", elastic_constants(1e6, 0.3)), "material 0");
  const tm_kernel& mooney = Registry::instance().get("mooney_rivlin", "tet4", "whole");
  EXPECT_THROW(laws.parameters(mooney), InputError);
}

}  // namespace
}  // namespace tensormass
