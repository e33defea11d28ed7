// A law's parameters through the C ABI: limits as messages read them, the
// arrays a kernel takes, and the refusals of wrong counts and values.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "kernel_test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/law_parameters.hpp"

namespace tmtest {
namespace {

using tensormass::InputError;

TEST(LawParameters, LimitsReadAsInequalities) {
  const double inf = HUGE_VAL;
  EXPECT_EQ(tensormass::describe_limit({0.0, inf, 0, 0}), "> 0");
  EXPECT_EQ(tensormass::describe_limit({-1.0, 0.5, 0, 0}), "> -1 and < 0.5");
  EXPECT_EQ(tensormass::describe_limit({0.0, 1.0, 1, 1}), ">= 0 and <= 1");
  EXPECT_EQ(tensormass::describe_limit({-inf, 3.0, 0, 0}), "< 3");
  EXPECT_EQ(tensormass::describe_limit({-inf, inf, 0, 0}), "finite");
  EXPECT_TRUE(tensormass::within_limit(0.0, {0.0, inf, 1, 0}));
  EXPECT_FALSE(tensormass::within_limit(0.0, {0.0, inf, 0, 0}));
  EXPECT_FALSE(tensormass::within_limit(0.5, {-1.0, 0.5, 0, 0}));
  EXPECT_FALSE(tensormass::within_limit(std::numeric_limits<double>::quiet_NaN(), {-inf, inf, 0, 0}));
  EXPECT_FALSE(tensormass::within_limit(inf, {-inf, inf, 0, 0}));
}

/// For every law: the array follows the kernel's order whatever the
/// constants' order, and the admissible values pass the kernel's own check.
TEST(LawParameters, ArraysFollowTheKernelsOrder) {
  for (const std::string& law : registry().laws()) {
    SCOPED_TRACE(law);
    const tm_kernel& kernel = *registry().law_kernel(law);
    const std::vector<double> admissible = tensormass::admissible_parameters(kernel);
    ASSERT_EQ(admissible.size(), static_cast<std::size_t>(kernel.params));
    std::map<std::string, double> constants;
    for (int p = 0; p < kernel.params; ++p) constants[kernel.param_names[p]] = admissible[p];
    EXPECT_EQ(tensormass::parameter_array(kernel, constants, "test"), admissible);
    const tm_element_info& element = element_of(kernel);
    std::vector<double> consts(static_cast<std::size_t>(kernel.consts));
    EXPECT_EQ(tensormass::precompute_checked(kernel, element.reference_nodes, admissible, consts.data(), "test"), 0);
  }
}

TEST(LawParameters, WrongCountsAndValuesAreInputErrorsNamingTheLaw) {
  const tm_kernel& kernel = registry().get("stvk", "tet4", "whole");
  const tm_element_info& element = element_of(kernel);
  std::vector<double> consts(static_cast<std::size_t>(kernel.consts));
  try {
    tensormass::precompute_checked(kernel, element.reference_nodes, std::vector<double>{1e6, 0.3, 7.0}, consts.data(),
                                   "material 2");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "material 2: law stvk takes 2 parameters (young, poisson), given 3");
  }
  try {
    tensormass::precompute_checked(kernel, element.reference_nodes, std::vector<double>{-1.0, 0.3}, consts.data(),
                                   "material 2");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "material 2: young must be > 0 for law stvk, got -1");
  }
  EXPECT_THROW(tensormass::parameter_array(kernel, {{"young", 1e6}}, "material 2"), InputError);
}

}  // namespace
}  // namespace tmtest
