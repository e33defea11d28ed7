// Helpers shared by the runtime test folders: a private temporary directory
// per test, and commands (the tensormass binary, python scripts) run
// through a shell with their output captured.
#ifndef TENSORMASS_TEST_SUPPORT_HPP
#define TENSORMASS_TEST_SUPPORT_HPP

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace test_support {

namespace fs = std::filesystem;

/// A fresh directory for the running test, removed at the end.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "_" + info->name();
    for (char& c : name)
      if (c == '/') c = '_';
    path_ = fs::temp_directory_path() / ("tensormass_test_" + std::to_string(::getpid()) + "_" + name);
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
  /// Writes `text` to `name` in this directory (creating folders); returns its path.
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path file = path_ / name;
    fs::create_directories(file.parent_path());
    std::ofstream(file) << text;
    return file.string();
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

#ifdef TENSORMASS_BINARY
/// Runs the tensormass binary with `arguments`.
inline Result tensormass(const std::string& arguments) { return shell(std::string(TENSORMASS_BINARY) + " " + arguments); }
#endif

}  // namespace test_support

#endif
