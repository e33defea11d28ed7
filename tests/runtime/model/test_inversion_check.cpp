// InversionCheck: det F at quadrature points and det dx/dxi at the corners,
// for every element of the registry.
#include <gtest/gtest.h>

#include <vector>

#include "tensormass/kernels/registry.hpp"
#include "tensormass/model/inversion_check.hpp"

namespace tensormass {
namespace {

std::vector<double> reference_positions(const tm_element_info& e) {
  return {e.reference_nodes, e.reference_nodes + e.nodes * e.dim};
}

class InversionCheckOfElement : public ::testing::TestWithParam<const tm_element_info*> {};

/// The reference element itself is positive at every corner (for a pyramid
/// apex too: its gradients are the limit from the centroid).
TEST_P(InversionCheckOfElement, ReferenceElementHasNoFlatCorner) {
  const tm_element_info& e = *GetParam();
  EXPECT_EQ(InversionCheck(e).first_flat_corner(reference_positions(e).data()), -1);
}

/// Mirrored (first coordinate negated), every corner's determinant changes
/// sign: the first corner is flat.
TEST_P(InversionCheckOfElement, MirroredElementIsFlatAtItsFirstCorner) {
  const tm_element_info& e = *GetParam();
  std::vector<double> x = reference_positions(e);
  for (int n = 0; n < e.nodes; ++n) x[static_cast<std::size_t>(n * e.dim)] *= -1;
  EXPECT_EQ(InversionCheck(e).first_flat_corner(x.data()), 0);
}

/// The corner gradients reproduce the reference map: sum_j xi_j (x) dN_j = I
/// at each corner, and the gradients sum to zero over the nodes.
TEST_P(InversionCheckOfElement, CornerGradientsReproduceTheReferenceMap) {
  const tm_element_info& e = *GetParam();
  for (int k = 0; k < e.corner_count; ++k) {
    const double* G = e.corner_gradients + k * e.nodes * e.dim;
    for (int a = 0; a < e.dim; ++a)
      for (int b = 0; b < e.dim; ++b) {
        double map = 0, sum = 0;
        for (int j = 0; j < e.nodes; ++j) {
          map += e.reference_nodes[j * e.dim + a] * G[j * e.dim + b];
          sum += G[j * e.dim + b];
        }
        EXPECT_NEAR(map, a == b ? 1.0 : 0.0, 1e-12) << e.name << " corner " << k;
        EXPECT_NEAR(sum, 0.0, 1e-12) << e.name << " corner " << k;
      }
  }
}

/// Only elements whose gradients vary need the corner check.
TEST_P(InversionCheckOfElement, CornersAreCheckedWhereTheGradientVaries) {
  const tm_element_info& e = *GetParam();
  const bool simplex_of_order_one = e.order == 1 && e.nodes == e.dim + 1;
  EXPECT_EQ(InversionCheck(e).checks_corners(), !simplex_of_order_one) << e.name;
}

std::string element_name(const ::testing::TestParamInfo<const tm_element_info*>& info) { return info.param->name; }

INSTANTIATE_TEST_SUITE_P(Registry, InversionCheckOfElement, ::testing::ValuesIn(Registry::instance().elements()),
                         element_name);

/// A unit hexahedron with corner 0 pushed to (0.45, 0.45, 0.45): every
/// Gauss point keeps det > 0 (about 0.02), the corner has det = 1 - 3 * 0.45 < 0.
TEST(InversionCheck, FindsAHexahedronFoldedAtACornerBetweenItsGaussPoints) {
  const tm_element_info* hex8 = Registry::instance().element("hex8");
  ASSERT_NE(hex8, nullptr);
  std::vector<double> x = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  x[0] = x[1] = x[2] = 0.45;
  EXPECT_EQ(InversionCheck(*hex8).first_flat_corner(x.data()), 0);
  x[0] = x[1] = x[2] = 0.3;  // 1 - 3 * 0.3 > 0
  EXPECT_EQ(InversionCheck(*hex8).first_flat_corner(x.data()), -1);
}

}  // namespace
}  // namespace tensormass
