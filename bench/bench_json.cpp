#include "bench_json.hpp"

#include <charconv>
#include <cmath>

namespace tensormass::bench {

Json number(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

Json number(double x, int digits) {
  if (!std::isfinite(x)) return nullptr;
  char text[32];
  const auto printed = std::to_chars(text, text + sizeof text, x, std::chars_format::general, digits);
  double rounded = x;
  std::from_chars(text, printed.ptr, rounded);
  return rounded;
}

Json numbers(const std::vector<double>& values) {
  Json list = Json::array();
  for (const double x : values) list.push_back(number(x));
  return list;
}

Json numbers(const std::vector<double>& values, int digits) {
  Json list = Json::array();
  for (const double x : values) list.push_back(number(x, digits));
  return list;
}

std::string json_text(const Json& json) { return json.dump(2, ' ', false, Json::error_handler_t::replace) + "\n"; }

}  // namespace tensormass::bench
