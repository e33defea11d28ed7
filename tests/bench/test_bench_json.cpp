// What the benchmarks' JSON writers share (bench/bench_json.hpp) and the
// "metadata" of their JSON objects (bench/bench_metadata.hpp).
#include <gtest/gtest.h>

#include <limits>
#include <regex>
#include <string>
#include <vector>

#include "bench_json.hpp"
#include "bench_metadata.hpp"
#include "machine_info.hpp"
#include "tensormass/common/version.hpp"

namespace tensormass::bench {
namespace {

TEST(BenchJson, NumbersAreNullWhereNotFinite) {
  EXPECT_EQ(number(0.015), 0.015);
  EXPECT_TRUE(number(std::numeric_limits<double>::quiet_NaN()).is_null());
  EXPECT_TRUE(number(-std::numeric_limits<double>::infinity(), 6).is_null());
  EXPECT_EQ(numbers({1.0, std::numeric_limits<double>::infinity()}), Json::parse("[1.0, null]"));
}

TEST(BenchJson, DigitsRoundLikePrintfG) {
  EXPECT_EQ(number(1234.56789, 6), 1234.57);
  EXPECT_EQ(number(0.000123456789, 4), 0.0001235);
  EXPECT_EQ(number(2.5e-7, 6), 2.5e-7);
  EXPECT_EQ(numbers({1.0 / 3.0, 27874.04}, 6), Json::parse("[0.333333, 27874.0]"));
  EXPECT_EQ(number(1.0 / 3.0, 6).dump(), "0.333333");
}

TEST(BenchJson, TextIsIndentedWithANewlineAndReplacesInvalidUtf8) {
  const Json json = {{"b", 1}, {"a", std::string("x\xff")}};
  const std::string text = json_text(json);
  EXPECT_EQ(text, "{\n  \"b\": 1,\n  \"a\": \"x\xef\xbf\xbd\"\n}\n");  // keys in order, U+FFFD
}

TEST(BenchMetadata, HasTheKeysInOrder) {
  const Json m = metadata();
  std::vector<std::string> keys;
  for (const auto& item : m.items()) keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"tensormass_version", "date", "commit", "machine", "threads"}));
  EXPECT_EQ(m["tensormass_version"], kVersion);
  EXPECT_TRUE(std::regex_match(m["date"].get<std::string>(), std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)")));
  EXPECT_FALSE(m["commit"].get<std::string>().empty());
  EXPECT_EQ(m["machine"], cpu_model());
  EXPECT_TRUE(m["threads"].is_number_integer());
  EXPECT_GE(m["threads"].get<int>(), 1);
}

}  // namespace
}  // namespace tensormass::bench
