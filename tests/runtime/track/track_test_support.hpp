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

namespace track_test {

namespace fs = std::filesystem;

/// A fresh directory for the running test, removed at the end.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "_" + info->name();
    for (char& c : name)
      if (c == '/') c = '_';
    path_ = fs::temp_directory_path() / ("tensormass_track_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const fs::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  /// Writes `text` to `name` in this directory; returns its path.
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name) << text;
    return file(name);
  }

 private:
  fs::path path_;
};

struct Result {
  int exit_code;
  std::string output;  ///< stdout and stderr
};

/// Runs a shell command, capturing stdout and stderr.
inline Result shell(const std::string& command) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  std::string output;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

/// Runs the tensormass binary with `arguments`.
inline Result tensormass(const std::string& arguments) { return shell(std::string(TENSORMASS_BINARY) + " " + arguments); }

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
