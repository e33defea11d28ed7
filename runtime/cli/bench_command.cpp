// `tensormass bench ARGS...`: the benchmarks are their own program,
// tensormass-bench (bench/), so that the CLI does not depend on them. This
// command replaces the process by it (execv: exit status and signals are
// its own), found beside this binary (a build tree, or an installed or
// relocated prefix), else in the bindir this build installs to.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "commands.hpp"

#ifndef TENSORMASS_INSTALL_BINDIR
#define TENSORMASS_INSTALL_BINDIR "/usr/local/bin"
#endif

namespace tensormass::cli {

namespace {

namespace fs = std::filesystem;

constexpr const char* kBenchProgram = "tensormass-bench";

/// Where tensormass-bench may be, in order.
std::vector<fs::path> candidates() {
  std::vector<fs::path> paths;
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (!error) paths.push_back(self.parent_path() / kBenchProgram);
  paths.push_back(fs::path(TENSORMASS_INSTALL_BINDIR) / kBenchProgram);
  return paths;
}

}  // namespace

int bench_command(const Arguments& args) {
  for (const fs::path& path : candidates()) {
    std::error_code error;
    if (!fs::is_regular_file(path, error) || access(path.c_str(), X_OK) != 0) continue;
    std::vector<std::string> words{kBenchProgram};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& word : words) argv.push_back(word.data());
    argv.push_back(nullptr);
    std::fflush(nullptr);
    execv(path.c_str(), argv.data());
    std::fprintf(stderr, "tensormass bench: cannot run %s: %s\n", path.c_str(), std::strerror(errno));
    return 2;
  }
  std::fprintf(stderr, "tensormass bench: benchmarks not built (configure with -DTENSORMASS_BUILD_BENCH=ON)\n");
  return 2;
}

}  // namespace tensormass::cli
