// A law's parameters through the C ABI (law_parameters.cpp): limits as
// messages read them, the names and arrays a kernel takes, admissible values
// within every limit, and the refusals of missing constants, wrong counts and
// values, naming the owner and the law; the per-kernel cases cover every
// kernel of the registry.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>
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

/// "a, b, c": the kernel's parameter names as the messages list them.
std::string listed_names(const tm_kernel& kernel) {
  std::string out;
  for (int p = 0; p < kernel.params; ++p) out += (p ? ", " : "") + std::string(kernel.param_names[p]);
  return out;
}

/// The admissible constants of `kernel` by name.
std::map<std::string, double> admissible_constants(const tm_kernel& kernel) {
  const std::vector<double> values = tensormass::admissible_parameters(kernel);
  std::map<std::string, double> constants;
  for (int p = 0; p < kernel.params; ++p) constants[kernel.param_names[p]] = values[p];
  return constants;
}

/// The message of the InputError parameter_array throws, or "no error".
std::string array_error(const tm_kernel& kernel, const std::map<std::string, double>& constants,
                        const std::string& owner) {
  try {
    tensormass::parameter_array(kernel, constants, owner);
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(LawParameters, NamesAreTheKernelsDistinctParametersInOrder) {
  for (const tm_kernel* kernel : all_kernels()) {
    SCOPED_TRACE(kernel_name(*kernel));
    const std::vector<std::string> names = tensormass::parameter_names(*kernel);
    ASSERT_EQ(names.size(), static_cast<std::size_t>(kernel->params));
    for (int p = 0; p < kernel->params; ++p) EXPECT_EQ(names[p], kernel->param_names[p]);
    EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  }
  EXPECT_EQ(tensormass::parameter_names(registry().get("stvk", "tet4", "whole")),
            (std::vector<std::string>{"young", "poisson"}));
}

TEST(LawParameters, AdmissibleParametersAreWithinEveryLimit) {
  for (const tm_kernel* kernel : all_kernels()) {
    SCOPED_TRACE(kernel_name(*kernel));
    const std::vector<double> values = tensormass::admissible_parameters(*kernel);
    ASSERT_EQ(values.size(), static_cast<std::size_t>(kernel->params));
    for (int p = 0; p < kernel->params; ++p)
      EXPECT_TRUE(tensormass::within_limit(values[p], kernel->param_limits[p]))
          << kernel->param_names[p] << " = " << values[p] << " is not "
          << tensormass::describe_limit(kernel->param_limits[p]);
  }
}

TEST(LawParameters, AdmissibleParametersTakeTheMiddleOrOnePastALimit) {
  const double inf = HUGE_VAL;
  const char* names[] = {"a", "b", "c", "d"};
  const tm_param_limit limits[] = {{-1.0, 0.5, 0, 0}, {2.0, inf, 1, 0}, {-inf, 3.0, 0, 1}, {-inf, inf, 0, 0}};
  tm_kernel kernel = registry().get("stvk", "tet4", "whole");
  kernel.params = 4;
  kernel.param_names = names;
  kernel.param_limits = limits;
  EXPECT_EQ(tensormass::admissible_parameters(kernel), (std::vector<double>{-0.25, 3.0, 2.0, 1.0}));
}

TEST(LawParameters, AMissingConstantIsAnErrorNamingOwnerLawAndConstant) {
  for (const tm_kernel* kernel : all_kernels()) {
    SCOPED_TRACE(kernel_name(*kernel));
    for (int p = 0; p < kernel->params; ++p) {
      std::map<std::string, double> constants = admissible_constants(*kernel);
      constants.erase(kernel->param_names[p]);
      if (tensormass::is_fibre_parameter(kernel->param_names[p])) {  // set per cell: a placeholder here
        EXPECT_EQ(array_error(*kernel, constants, "scene.yaml: materials[1]"), "no error");
        continue;
      }
      EXPECT_EQ(array_error(*kernel, constants, "scene.yaml: materials[1]"),
                "scene.yaml: materials[1]: law " + std::string(kernel->law) + " needs the constant '" +
                    kernel->param_names[p] + "' (its parameters: " + listed_names(*kernel) + ")");
    }
  }
}

TEST(LawParameters, AConstantOutsideItsLimitIsAnErrorNamingOwnerLawAndLimit) {
  for (const tm_kernel* kernel : all_kernels()) {
    SCOPED_TRACE(kernel_name(*kernel));
    for (int p = 0; p < kernel->params; ++p) {
      const tm_param_limit& limit = kernel->param_limits[p];
      const std::string name = kernel->param_names[p];
      std::vector<double> refused{std::numeric_limits<double>::quiet_NaN(), HUGE_VAL};
      if (std::isfinite(limit.lower)) refused.push_back(limit.lower_inclusive ? limit.lower - 1 : limit.lower);
      if (std::isfinite(limit.upper)) refused.push_back(limit.upper_inclusive ? limit.upper + 1 : limit.upper);
      for (double value : refused) {
        SCOPED_TRACE(name + " = " + std::to_string(value));
        std::map<std::string, double> constants = admissible_constants(*kernel);
        constants[name] = value;
        const std::string message = array_error(*kernel, constants, "materials[0]");
        const std::string expected = "materials[0]: " + name + " must be " + tensormass::describe_limit(limit) +
                                     " for law " + kernel->law + ", got ";
        EXPECT_EQ(message.substr(0, expected.size()), expected) << message;
      }
    }
  }
}

TEST(LawParameters, TheBadValueIsGivenInFull) {
  const tm_kernel& kernel = registry().get("stvk", "tet4", "whole");
  EXPECT_EQ(array_error(kernel, {{"young", 1e6}, {"poisson", 0.5}}, "m"),
            "m: poisson must be " + tensormass::describe_limit(kernel.param_limits[1]) + " for law stvk, got 0.5");
  EXPECT_EQ(array_error(kernel, {{"young", -1234567.875}, {"poisson", 0.3}}, "m"),
            "m: young must be > 0 for law stvk, got -1234567.875");
}

TEST(LawParameters, ConstantsOfOtherLawsAreIgnored) {
  // A material's constants serve every law it may switch to: a kernel takes its own.
  for (const tm_kernel* kernel : all_kernels()) {
    SCOPED_TRACE(kernel_name(*kernel));
    std::map<std::string, double> constants = admissible_constants(*kernel);
    constants["not_a_parameter_of_any_law"] = -1.0;
    EXPECT_EQ(tensormass::parameter_array(*kernel, constants, "m"), tensormass::admissible_parameters(*kernel));
  }
}

}  // namespace
}  // namespace tmtest
