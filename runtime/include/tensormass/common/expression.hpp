/// \file expression.hpp
/// A scalar formula of named variables read from a scene ("-y", "x / sqrt(x^2 +
/// y^2)"): numbers, the variables, pi, + - * / ^ (or **), parentheses and the
/// functions sin cos tan asin acos atan atan2 sqrt exp log abs min max.
/// Compiled once to a postfix program, then evaluated without allocating.
#ifndef TENSORMASS_COMMON_EXPRESSION_HPP
#define TENSORMASS_COMMON_EXPRESSION_HPP

#include <span>
#include <string>
#include <vector>

namespace tensormass {

class Expression {
 public:
  /// Parses `text` over `variables` (their order is the order of the values
  /// `evaluate` takes); InputError "<owner>: <what is wrong> at column N"
  /// on a syntax error, an unknown name or a nesting deeper than 64.
  Expression(const std::string& text, const std::vector<std::string>& variables, const std::string& owner);
  Expression() = default;

  /// The value at `values` (one per variable); NaN or inf where the formula
  /// is undefined there (the caller names the point).
  double evaluate(std::span<const double> values) const;
  const std::string& text() const { return text_; }

  /// One step of the postfix program.
  struct Step {
    int code = 0;        ///< what the step does (expression.cpp's OpCode)
    double value = 0.0;  ///< the number pushed, or the variable's index
  };

 private:
  std::string text_;
  std::vector<Step> program_;
  int stack_depth_ = 0;
};

}  // namespace tensormass

#endif
