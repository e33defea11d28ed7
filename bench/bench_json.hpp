/// \file bench_json.hpp
/// What the benchmarks' JSON writers share: nlohmann-json's ordered_json
/// (keys keep the order they are set in), numbers (null where not finite)
/// and the text written to the files.
#ifndef TENSORMASS_BENCH_BENCH_JSON_HPP
#define TENSORMASS_BENCH_BENCH_JSON_HPP

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace tensormass::bench {

using Json = nlohmann::ordered_json;

/// A number, or null where it is not finite (JSON has no NaN or infinity).
Json number(double x);
/// The same, rounded to `digits` significant digits (printf's %.*g): the
/// precision a benchmark has always written its figures with.
Json number(double x, int digits);
/// A list of number(x) or of number(x, digits).
Json numbers(const std::vector<double>& values);
Json numbers(const std::vector<double>& values, int digits);

/// `json` indented by two, with a final newline; invalid UTF-8 in a string
/// (a name) is replaced, not thrown on.
std::string json_text(const Json& json);

}  // namespace tensormass::bench

#endif
