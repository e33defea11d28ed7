#include "tensormass/common/expression.hpp"

#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <numbers>

#include "tensormass/common/errors.hpp"

namespace tensormass {

namespace {

enum OpCode {
  kNumber,
  kVariable,
  kAdd,
  kSubtract,
  kMultiply,
  kDivide,
  kPower,
  kNegate,
  kSin,
  kCos,
  kTan,
  kAsin,
  kAcos,
  kAtan,
  kSqrt,
  kExp,
  kLog,
  kAbs,
  kAtan2,
  kMin,
  kMax
};

struct Function {
  const char* name;
  int arguments;
  OpCode code;
};

constexpr std::array<Function, 13> kFunctions = {{{"sin", 1, kSin},
                                                  {"cos", 1, kCos},
                                                  {"tan", 1, kTan},
                                                  {"asin", 1, kAsin},
                                                  {"acos", 1, kAcos},
                                                  {"atan", 1, kAtan},
                                                  {"sqrt", 1, kSqrt},
                                                  {"exp", 1, kExp},
                                                  {"log", 1, kLog},
                                                  {"abs", 1, kAbs},
                                                  {"atan2", 2, kAtan2},
                                                  {"min", 2, kMin},
                                                  {"max", 2, kMax}}};

constexpr int kMaxNesting = 64;
constexpr int kMaxStack = 256;

/// Recursive descent: expression := term (+|- term)*, term := unary (*|/
/// unary)*, unary := (-|+) unary | power, power := primary (^ unary)?,
/// primary := number | variable | pi | function(args) | (expression).
class Parser {
 public:
  Parser(const std::string& text, const std::vector<std::string>& variables, const std::string& owner)
      : text_(text), variables_(variables), owner_(owner) {}

  std::vector<Expression::Step> parse() {
    expression(0);
    skip_space();
    if (at_ < text_.size()) fail("unexpected '" + std::string(1, text_[at_]) + "'");
    return std::move(program_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(owner_ + ": formula '" + text_ + "': " + what + " at column " + std::to_string(at_ + 1));
  }
  void skip_space() {
    while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
  }
  bool accept(const char* token) {
    skip_space();
    const std::string_view t(token);
    if (text_.compare(at_, t.size(), t) != 0) return false;
    at_ += t.size();
    return true;
  }
  void emit(int code, double value = 0.0) { program_.push_back({code, value}); }
  void nest(int depth) const {
    if (depth > kMaxNesting) fail("nested deeper than " + std::to_string(kMaxNesting));
  }

  void expression(int depth) {
    nest(depth);
    term(depth);
    for (;;) {
      if (accept("+")) {
        term(depth);
        emit(kAdd);
      } else if (accept("-")) {
        term(depth);
        emit(kSubtract);
      } else {
        return;
      }
    }
  }
  void term(int depth) {
    unary(depth);
    for (;;) {
      skip_space();
      if (text_.compare(at_, 2, "**") == 0) return;  // a power, read by `power`
      if (accept("*")) {
        unary(depth);
        emit(kMultiply);
      } else if (accept("/")) {
        unary(depth);
        emit(kDivide);
      } else {
        return;
      }
    }
  }
  void unary(int depth) {
    nest(depth);
    if (accept("-")) {
      unary(depth + 1);
      emit(kNegate);
    } else if (accept("+")) {
      unary(depth + 1);
    } else {
      power(depth);
    }
  }
  void power(int depth) {
    primary(depth);
    if (accept("^") || accept("**")) {
      unary(depth + 1);  // right-associative: 2^3^2 = 2^9
      emit(kPower);
    }
  }
  void primary(int depth) {
    nest(depth);
    skip_space();
    if (at_ >= text_.size()) fail("expected a number, a name or '('");
    const char c = text_[at_];
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return number();
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') return name(depth);
    if (accept("(")) {
      expression(depth + 1);
      if (!accept(")")) fail("expected ')'");
      return;
    }
    fail("unexpected '" + std::string(1, c) + "'");
  }
  void number() {
    const char* begin = text_.c_str() + at_;
    char* end = nullptr;
    const double value = std::strtod(begin, &end);
    if (end == begin || !std::isfinite(value)) fail("bad number");
    at_ += static_cast<std::size_t>(end - begin);
    emit(kNumber, value);
  }
  void name(int depth) {
    const std::size_t start = at_;
    while (at_ < text_.size() && (std::isalnum(static_cast<unsigned char>(text_[at_])) || text_[at_] == '_')) ++at_;
    const std::string word = text_.substr(start, at_ - start);
    for (std::size_t v = 0; v < variables_.size(); ++v)
      if (word == variables_[v]) return emit(kVariable, static_cast<double>(v));
    if (word == "pi") return emit(kNumber, std::numbers::pi);
    for (const Function& function : kFunctions) {
      if (word != function.name) continue;
      if (!accept("(")) fail("expected '(' after " + word);
      for (int a = 0; a < function.arguments; ++a) {
        if (a > 0 && !accept(",")) fail(word + " takes " + std::to_string(function.arguments) + " arguments");
        expression(depth + 1);
      }
      if (!accept(")")) fail("expected ')' closing " + word);
      return emit(function.code);
    }
    at_ = start;
    std::string known;
    for (const std::string& v : variables_) known += v + ", ";
    fail("unknown name '" + word + "' (variables: " + known + "pi; functions: sin cos tan asin acos atan atan2 " +
         "sqrt exp log abs min max)");
  }

  const std::string& text_;
  const std::vector<std::string>& variables_;
  const std::string& owner_;
  std::size_t at_ = 0;
  std::vector<Expression::Step> program_;
};

double apply(int code, double a) {
  switch (code) {
    case kNegate: return -a;
    case kSin: return std::sin(a);
    case kCos: return std::cos(a);
    case kTan: return std::tan(a);
    case kAsin: return std::asin(a);
    case kAcos: return std::acos(a);
    case kAtan: return std::atan(a);
    case kSqrt: return std::sqrt(a);
    case kExp: return std::exp(a);
    case kLog: return std::log(a);
    default: return std::abs(a);  // kAbs
  }
}

double apply(int code, double a, double b) {
  switch (code) {
    case kAdd: return a + b;
    case kSubtract: return a - b;
    case kMultiply: return a * b;
    case kDivide: return a / b;
    case kPower: return std::pow(a, b);
    case kAtan2: return std::atan2(a, b);
    case kMin: return std::fmin(a, b);
    default: return std::fmax(a, b);  // kMax
  }
}

bool binary(int code) {
  return code == kAdd || code == kSubtract || code == kMultiply || code == kDivide || code == kPower ||
         code == kAtan2 || code == kMin || code == kMax;
}

}  // namespace

Expression::Expression(const std::string& text, const std::vector<std::string>& variables, const std::string& owner)
    : text_(text), program_(Parser(text, variables, owner).parse()) {
  int depth = 0;
  for (const Step& step : program_) {
    depth += step.code == kNumber || step.code == kVariable ? 1 : binary(step.code) ? -1 : 0;
    stack_depth_ = std::max(stack_depth_, depth);
  }
  if (stack_depth_ > kMaxStack)
    throw InputError(owner + ": formula '" + text + "' needs more than " + std::to_string(kMaxStack) +
                     " intermediate values; split it");
}

double Expression::evaluate(std::span<const double> values) const {
  std::array<double, kMaxStack> stack;
  int top = 0;
  for (const Step& step : program_) {
    if (step.code == kNumber) {
      stack[top++] = step.value;
    } else if (step.code == kVariable) {
      stack[top++] = values[static_cast<std::size_t>(step.value)];
    } else if (binary(step.code)) {
      --top;
      stack[top - 1] = apply(step.code, stack[top - 1], stack[top]);
    } else {
      stack[top - 1] = apply(step.code, stack[top - 1]);
    }
  }
  return top == 1 ? stack[0] : std::nan("");
}

}  // namespace tensormass
