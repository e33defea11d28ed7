/// \file test_support.hpp
/// The helpers every C++ test shares: a private temporary directory, file
/// reading, and commands (a shell line, the tensormass binary, a python
/// script) run with their output captured. The one place for these: a test
/// folder's own support header adds only what is particular to its tests.
#ifndef TENSORMASS_TESTS_SUPPORT_TEST_SUPPORT_HPP
#define TENSORMASS_TESTS_SUPPORT_TEST_SUPPORT_HPP

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace test_support {

namespace fs = std::filesystem;

/// A fresh empty directory under the system temporary directory, named
/// after the running test (or test suite, in SetUpTestSuite), removed with
/// its content on destruction.
class TempDir {
 public:
  TempDir() {
    static int counter = 0;
    std::string name = "tensormass_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
    const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
    if (const ::testing::TestInfo* test = unit.current_test_info())
      name += std::string("_") + test->test_suite_name() + "_" + test->name();
    else if (const ::testing::TestSuite* suite = unit.current_test_suite()) name += std::string("_") + suite->name();
    std::replace(name.begin(), name.end(), '/', '_');
    path_ = fs::temp_directory_path() / name;
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
  /// The path of `name` in this directory.
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  /// Writes `content` (bytes as given) to `name` in this directory, creating
  /// folders; returns its path.
  std::string write(const std::string& name, const std::string& content) const {
    const fs::path target = path_ / name;
    fs::create_directories(target.parent_path());
    std::ofstream(target, std::ios::binary) << content;
    return target.string();
  }
  /// Names of the files in the directory, sorted.
  std::vector<std::string> files() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(path_)) names.push_back(entry.path().filename());
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  fs::path path_;
};

/// The whole content of a file (empty when it cannot be read).
inline std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The lines of a text file, without their line ends.
inline std::vector<std::string> read_lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// Expects `message` to contain every one of `parts`.
inline void expect_contains(const std::string& message, const std::vector<std::string>& parts) {
  for (const std::string& part : parts)
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' missing in: " << message;
}

/// What a command did: its exit status (-1 when it did not exit normally)
/// and its output.
struct Result {
  int exit_code;
  std::string output;  ///< stdout and stderr together (shell), or stdout alone (shell_apart)
  std::string error;   ///< stderr (shell_apart only)
};

/// Runs `command` through /bin/sh, reading its stdout; the exit status and what it printed.
inline Result read_command(const std::string& command) {
  Result result{-1, {}, {}};
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) result.output.append(buffer, n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

/// Runs a shell command, capturing stdout and stderr together in `output`.
inline Result shell(const std::string& command) { return read_command("{ " + command + "\n} 2>&1"); }

/// Runs a shell command, capturing stdout in `output` and stderr in `error`.
inline Result shell_apart(const std::string& command) {
  const TempDir scratch;
  const std::string errors = scratch.file("stderr.txt");
  Result result = read_command("{ " + command + "\n} 2>'" + errors + "'");
  result.error = read_file(errors);
  return result;
}

/// Runs /usr/bin/python3 with `arguments` (a script and its arguments, or -c CODE ...).
inline Result python(const std::string& arguments) { return shell("/usr/bin/python3 " + arguments); }

#ifdef TENSORMASS_SOURCE_DIR
/// A path in the source tree, relative to its root.
inline std::string source_path(const std::string& relative) {
  return std::string(TENSORMASS_SOURCE_DIR) + "/" + relative;
}
#endif

#ifdef TENSORMASS_BINARY
/// Runs the tensormass binary with `arguments` (stdout and stderr together).
inline Result tensormass(const std::string& arguments) { return shell("'" TENSORMASS_BINARY "' " + arguments); }
#endif

}  // namespace test_support

#endif
