// Errors met by some MPI ranks thrown on all (tensormass/parallel/rank_errors.hpp):
// on one rank the work runs as it is, its exception untouched; under
// mpirun -n 3 (this test binary started again on three ranks) rank 0's error
// in on_root, and the lowest failing rank's in on_every_rank, reach every
// rank with its kind and message. (Whole runs failing on one rank under
// mpirun: parallel/check_mpi_runs.py.)
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/parallel/mpi_world.hpp"
#include "tensormass/parallel/rank_errors.hpp"

namespace tensormass {
namespace {

constexpr const char* kRanksDirectory = "TENSORMASS_TEST_RANK_ERRORS_DIRECTORY";

/// "InputError: message", "NumericalError: ...", "runtime_error: ...",
/// "other: ..." or "none": what `action` threw.
template <class Action>
std::string thrown(Action action) {
  try {
    action();
  } catch (const NotPositiveDefiniteError& error) {
    return std::string("NotPositiveDefiniteError: ") + error.what();
  } catch (const InputError& error) {
    return std::string("InputError: ") + error.what();
  } catch (const NumericalError& error) {
    return std::string("NumericalError: ") + error.what();
  } catch (const OutputError& error) {
    return std::string("OutputError: ") + error.what();
  } catch (const std::runtime_error& error) {
    return std::string("runtime_error: ") + error.what();
  } catch (const std::exception& error) {
    return std::string("other: ") + error.what();
  }
  return "none";
}

/// What each rank reports of the scenarios below, in order.
std::string rank_report() {
  using parallel::on_every_rank;
  using parallel::on_root;
  const int rank = parallel::world_rank();
  const std::string me = std::to_string(rank);
  int root_calls = 0;
  std::string report;
  // Throws `error` from the work on_root runs (on rank 0 alone).
  const auto root_throwing = [&](auto error) {
    return thrown([&] {
      on_root([&] {
        ++root_calls;
        throw error;
      });
    });
  };
  report += "root input: " + root_throwing(InputError("bad mesh")) + "\n";
  report += "root numerical: " + root_throwing(NumericalError("NaN")) + "\n";
  report += "root output: " + root_throwing(OutputError("disk full")) + "\n";
  report += "root fine: " + thrown([&] { on_root([&] { ++root_calls; }); }) + "\n";
  report += "root calls here: " + std::to_string(root_calls) + "\n";
  report += "every, ranks 1 and 2 fail: " + thrown([&] {
              on_every_rank([&] {
                if (rank > 0) throw InputError("rank " + me);
              });
            }) +
            "\n";
  report += "every, rank 2 fails: " + thrown([&] {
              on_every_rank([&] {
                if (rank == 2) throw NumericalError("inverted on rank " + me);
              });
            }) +
            "\n";
  report += "every, all fail: " + thrown([&] { on_every_rank([&] { throw std::logic_error("rank " + me); }); }) + "\n";
  report += "every fine: " + thrown([&] { on_every_rank([] {}); }) + "\n";
  return report;
}

// In the processes mpirun starts from this binary (below), each rank writes
// its report and the process ends before any test runs.
const bool kReportedOnRanks = [] {
  const char* directory = std::getenv(kRanksDirectory);
  if (directory == nullptr) return false;
  parallel::start_world();
  const std::string report = rank_report();
  std::ofstream(std::string(directory) + "/rank" + std::to_string(parallel::world_rank()) + ".txt") << report;
  parallel::finish_world();
  std::_Exit(0);
}();

TEST(RankErrors, OnOneRankTheWorkRunsOnceAndItsExceptionIsUntouched) {
  int calls = 0;
  parallel::on_root([&] { ++calls; });
  parallel::on_every_rank([&] { ++calls; });
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(thrown([] { parallel::on_root([] { throw OutputError("out.vtu: disk full"); }); }),
            "OutputError: out.vtu: disk full");
  EXPECT_EQ(thrown([] { parallel::on_every_rank([] { throw NotPositiveDefiniteError("indefinite"); }); }),
            "NotPositiveDefiniteError: indefinite");
  EXPECT_EQ(thrown([] { parallel::on_every_rank([] { throw std::logic_error("bug"); }); }), "other: bug");
  EXPECT_EQ(thrown([] { parallel::on_root([] { throw InputError("m.msh:3: bad"); }); }), "InputError: m.msh:3: bad");
}

TEST(RankErrors, OnThreeRanksEveryRankThrowsTheSameError) {
  if (!petsc_available()) GTEST_SKIP() << "this build has no PETSc, so no MPI";
  if (test_support::shell("command -v mpirun").exit_code != 0)
    GTEST_SKIP() << "no mpirun (apt-get install openmpi-bin)";
  const test_support::TempDir dir;
  std::string command = std::string(kRanksDirectory) + "='" + dir.path().string() + "' ";
  if (::geteuid() == 0) command += "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ";
  command +=
      "timeout 120 mpirun -n 3 --oversubscribe '" + std::filesystem::read_symlink("/proc/self/exe").string() + "'";
  const test_support::Result result = test_support::shell(command);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string shared =
      "root input: InputError: bad mesh\n"
      "root numerical: NumericalError: NaN\n"
      "root output: OutputError: disk full\n"  // input, numerical and output errors keep their kind
      "root fine: none\n";
  const std::string after =
      "every, ranks 1 and 2 fail: InputError: rank 1\n"
      "every, rank 2 fails: NumericalError: inverted on rank 2\n"
      "every, all fail: runtime_error: rank 0\n"
      "every fine: none\n";
  for (int rank = 0; rank < 3; ++rank)
    EXPECT_EQ(test_support::read_file(dir.file("rank" + std::to_string(rank) + ".txt")),
              shared + "root calls here: " + (rank == 0 ? "4" : "0") + "\n" + after)
        << "rank " << rank;
}

}  // namespace
}  // namespace tensormass
