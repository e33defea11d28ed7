// Helpers of the track tests: a private temporary directory per test, the
// tensormass binary and python scripts run through a shell, CSV reading.
#ifndef TENSORMASS_TRACK_TEST_SUPPORT_HPP
#define TENSORMASS_TRACK_TEST_SUPPORT_HPP

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace track_test {

namespace fs = std::filesystem;

using test_support::Result;
using test_support::shell;
using test_support::TempDir;
using test_support::tensormass;

inline std::string read(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The lines of a text file.
inline std::vector<std::string> lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

/// The numbers of a CSV row.
inline std::vector<double> numbers(const std::string& row) {
  std::vector<double> out;
  std::stringstream in(row);
  for (std::string field; std::getline(in, field, ',');) out.push_back(std::stod(field));
  return out;
}

}  // namespace track_test

#endif
