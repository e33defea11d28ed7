// The OpenMP wait policy programs start with (tensormass/common/thread_defaults.hpp):
// a process without OMP_WAIT_POLICY starts again with passive waiting and a
// short spin, its arguments unchanged; the user's settings are kept. (What a
// whole `tensormass run` reports it used: cli/test_run_command.cpp.)
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>

#include "support/test_support.hpp"
#include "tensormass/common/thread_defaults.hpp"

namespace {

using test_support::TempDir;

constexpr const char* kReportVariable = "TENSORMASS_TEST_WAIT_POLICY_REPORT";

std::string variable(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "unset";
}

/// "HOW OMP_WAIT_POLICY=... GOMP_SPINCOUNT=..." written to the report file.
void write_report(const char* how) {
  std::string arguments = test_support::read_file("/proc/self/cmdline");
  std::replace(arguments.begin(), arguments.end(), '\0', '|');
  std::ofstream(std::getenv(kReportVariable)) << how << " OMP_WAIT_POLICY=" << variable("OMP_WAIT_POLICY")
                                              << " GOMP_SPINCOUNT=" << variable("GOMP_SPINCOUNT") << "\n"
                                              << arguments;
}

// In the process apply_default_wait_policy starts again (below), the report
// is written and the process ends before any test runs.
const bool kReportedAtStart = [] {
  if (std::getenv(kReportVariable) == nullptr) return false;
  write_report("re-executed");
  std::_Exit(0);
}();

/// Calls apply_default_wait_policy in a child process with OMP_WAIT_POLICY
/// and GOMP_SPINCOUNT as given (nullptr: unset); what the child, or the
/// process it started again, reported.
std::string report_of_child(const char* wait_policy, const char* spin_count) {
  const TempDir dir;
  const std::string report = dir.file("report.txt");
  const pid_t child = ::fork();
  if (child == 0) {
    const int quiet = ::open("/dev/null", O_WRONLY);
    ::dup2(quiet, STDOUT_FILENO);
    wait_policy ? ::setenv("OMP_WAIT_POLICY", wait_policy, 1) : ::unsetenv("OMP_WAIT_POLICY");
    spin_count ? ::setenv("GOMP_SPINCOUNT", spin_count, 1) : ::unsetenv("GOMP_SPINCOUNT");
    ::setenv(kReportVariable, report.c_str(), 1);
    char* argv[] = {const_cast<char*>("common_tests"), const_cast<char*>("--first"),
                    const_cast<char*>("a second argument"), nullptr};
    tensormass::apply_default_wait_policy(argv);
    write_report("returned");
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  return test_support::read_file(report);
}

/// The first line of a report.
std::string first_line(const std::string& report) { return report.substr(0, report.find('\n')); }

TEST(ThreadDefaults, WithoutAPolicyTheProcessStartsAgainWaitingPassivelyAfterAShortSpin) {
  const std::string report = report_of_child(nullptr, nullptr);
  EXPECT_EQ(first_line(report), "re-executed OMP_WAIT_POLICY=passive GOMP_SPINCOUNT=10000") << report;
}

TEST(ThreadDefaults, TheProcessStartedAgainHasTheSameArguments) {
  const std::string report = report_of_child(nullptr, nullptr);
  EXPECT_EQ(report.substr(report.find('\n') + 1), "common_tests|--first|a second argument|") << report;
}

TEST(ThreadDefaults, TheUsersSpinCountIsKept) {
  EXPECT_EQ(first_line(report_of_child(nullptr, "0")), "re-executed OMP_WAIT_POLICY=passive GOMP_SPINCOUNT=0");
}

TEST(ThreadDefaults, TheUsersPolicyIsKeptWithoutStartingAgain) {
  EXPECT_EQ(first_line(report_of_child("active", nullptr)), "returned OMP_WAIT_POLICY=active GOMP_SPINCOUNT=unset");
  EXPECT_EQ(first_line(report_of_child("passive", "5")), "returned OMP_WAIT_POLICY=passive GOMP_SPINCOUNT=5");
  // Set, even to nothing, is the user's choice.
  EXPECT_EQ(first_line(report_of_child("", nullptr)), "returned OMP_WAIT_POLICY= GOMP_SPINCOUNT=unset");
}

}  // namespace
