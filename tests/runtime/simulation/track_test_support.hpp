// Helpers of the track tests: test_support's temporary directory and
// tensormass runner, and the numbers of a track CSV row.
#ifndef TENSORMASS_TRACK_TEST_SUPPORT_HPP
#define TENSORMASS_TRACK_TEST_SUPPORT_HPP

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace track_test {

using test_support::read_file;
using test_support::read_lines;
using test_support::Result;
using test_support::TempDir;
using test_support::tensormass;

/// The numbers of a CSV row.
inline std::vector<double> numbers(const std::string& row) {
  std::vector<double> out;
  std::stringstream in(row);
  for (std::string field; std::getline(in, field, ',');) out.push_back(std::stod(field));
  return out;
}

}  // namespace track_test

#endif
