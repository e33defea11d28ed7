// Scene formulas (expression.cpp): precedence, associativity, functions and
// variables against the same arithmetic in C++, and errors with the column.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "tensormass/common/errors.hpp"
#include "tensormass/common/expression.hpp"

namespace tensormass {
namespace {

double value(const std::string& text, std::vector<double> at = {0.3, -1.7, 2.5}) {
  return Expression(text, {"x", "y", "z"}, "test").evaluate(at);
}

std::string error_of(const std::string& text) {
  try {
    Expression(text, {"x", "y", "z"}, "scene.yaml:4: materials[0].fibres");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Expression, FollowsTheUsualPrecedence) {
  const double x = 0.3, y = -1.7, z = 2.5;
  EXPECT_DOUBLE_EQ(value("1 + 2 * 3 - 4 / 8"), 1 + 2 * 3 - 4.0 / 8);
  EXPECT_DOUBLE_EQ(value("-x^2"), -(x * x));
  EXPECT_DOUBLE_EQ(value("2^3^2"), 512.0);
  EXPECT_DOUBLE_EQ(value("2**-1"), 0.5);
  EXPECT_DOUBLE_EQ(value("(x + y) * z"), (x + y) * z);
  EXPECT_DOUBLE_EQ(value("x - y - z"), x - y - z);
  EXPECT_DOUBLE_EQ(value("x / y / z"), x / y / z);
  EXPECT_DOUBLE_EQ(value("1.5e-3 * +y"), 1.5e-3 * y);
}

TEST(Expression, ReadsVariablesFunctionsAndPi) {
  const double x = 0.3, y = -1.7, z = 2.5;
  EXPECT_DOUBLE_EQ(value("x / sqrt(x^2 + y^2)"), x / std::sqrt(x * x + y * y));
  EXPECT_DOUBLE_EQ(value("atan2(y, x) + cos(pi * z)"), std::atan2(y, x) + std::cos(std::numbers::pi * z));
  EXPECT_DOUBLE_EQ(value("min(x, y) + max(x, z) + abs(y) + exp(x) + log(z)"),
                   std::min(x, y) + std::max(x, z) + std::abs(y) + std::exp(x) + std::log(z));
  EXPECT_DOUBLE_EQ(value("sin(x) + tan(x) + asin(x) + acos(x) + atan(y)"),
                   std::sin(x) + std::tan(x) + std::asin(x) + std::acos(x) + std::atan(y));
  EXPECT_TRUE(std::isnan(value("sqrt(y)")));
}

TEST(Expression, ErrorsNameTheOwnerAndColumn) {
  EXPECT_EQ(error_of("x + w"),
            "scene.yaml:4: materials[0].fibres: formula 'x + w': unknown name 'w' (variables: x, y, z, pi; functions: "
            "sin cos tan asin acos atan atan2 sqrt exp log abs min max) at column 5");
  EXPECT_NE(error_of("x +").find("expected a number, a name or '(' at column 4"), std::string::npos);
  EXPECT_NE(error_of("(x").find("expected ')' at column 3"), std::string::npos);
  EXPECT_NE(error_of("x y").find("unexpected 'y' at column 3"), std::string::npos);
  EXPECT_NE(error_of("atan2(x)").find("atan2 takes 2 arguments"), std::string::npos);
  EXPECT_NE(error_of("sqrt x").find("expected '(' after sqrt"), std::string::npos);
  EXPECT_NE(error_of("").find("at column 1"), std::string::npos);
  EXPECT_NE(error_of("1e999").find("bad number"), std::string::npos);
}

TEST(Expression, DeepNestingIsRefusedNotOverflowed) {
  EXPECT_NE(error_of(std::string(100000, '(') + "x" + std::string(100000, ')')).find("nested deeper than 64"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(100000, '-') + "x").find("nested deeper than 64"), std::string::npos);
  EXPECT_DOUBLE_EQ(value(std::string(30, '(') + "x" + std::string(30, ')')), 0.3);
}

}  // namespace
}  // namespace tensormass
