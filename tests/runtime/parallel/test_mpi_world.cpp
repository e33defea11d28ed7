// The MPI ranks a run spans (tensormass/parallel/mpi_world.hpp): a process
// no launcher started is one rank whose collectives give back what they
// were given (in a build with or without PETSc); under mpirun -n 3 (this
// test binary started again on three ranks) sums, maxima, gathers,
// broadcasts, sends, neighbour exchanges, the lowest rank holding a minimum
// and the exit after an error met everywhere, checked on every rank.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/parallel/mpi_world.hpp"

namespace tensormass::parallel {
namespace {

constexpr const char* kRanksDirectory = "TENSORMASS_TEST_MPI_WORLD_DIRECTORY";
constexpr const char* kLauncherVariables[] = {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"};

std::string text(const std::vector<char>& bytes) { return {bytes.begin(), bytes.end()}; }

/// What this rank finds of each collective, one line each.
std::string rank_report() {
  const int rank = world_rank();
  std::ostringstream out;
  out << "ranks: " << world_size() << "\n";
  out << "sum: " << sum_over_ranks(rank + 0.5) << "\n";
  std::vector<double> parts(3, 0.0);
  parts[rank] = rank + 1.0;
  sum_over_ranks(parts);
  out << "sum in place: " << parts[0] << " " << parts[1] << " " << parts[2] << "\n";
  out << "max: " << max_over_ranks(10.0 - rank) << "\n";
  out << "gathered:";
  for (double value : gather_to_root(10.0 * rank)) out << " " << value;
  out << "\n";
  std::vector<int> ints = rank == 0 ? std::vector<int>{7, 8, 9} : std::vector<int>{0, 0, 0};
  broadcast_from_root(ints);
  out << "broadcast: " << ints[0] << " " << ints[1] << " " << ints[2] << "\n";
  std::vector<char> bytes;
  if (rank == 0) bytes = {'h', 'e', 'l', 'l', 'o'};
  broadcast_bytes_from_root(bytes);
  out << "bytes from root: " << text(bytes) << "\n";
  bytes = rank == 2 ? std::vector<char>{'t', 'w', 'o'} : std::vector<char>(9, 'x');
  broadcast_bytes_from(2, bytes);
  out << "bytes from rank 2: " << text(bytes) << "\n";
  if (rank == 0) {
    send_bytes_from_root(1, {'f', 'o', 'r', ' ', '1'});
    send_bytes_from_root(2, {'r', 'a', 'n', 'k', ' ', 't', 'w', 'o'});
  } else {
    out << "received: " << text(receive_bytes_from_root()) << "\n";
  }
  const std::vector<int> neighbours{(rank + 1) % 3, (rank + 2) % 3};
  const std::vector<std::vector<double>> send{{100.0 * rank + neighbours[0]}, {100.0 * rank + neighbours[1], -1.0}};
  // Each rank sends 1 value to rank + 1 and 2 to rank + 2: it gets 2 from
  // rank + 1 (for which it is rank + 2) and 1 from rank + 2.
  std::vector<std::vector<double>> receive{std::vector<double>(2), std::vector<double>(1)};
  exchange_with_neighbours(neighbours, send, receive);
  out << "from rank " << neighbours[0] << ":";
  for (double value : receive[0]) out << " " << value;
  out << "; from rank " << neighbours[1] << ":";
  for (double value : receive[1]) out << " " << value;
  out << "\n";
  const int values[3] = {5, 3, 3};
  const RankedValue least = min_over_ranks(values[rank]);
  out << "min: " << least.value << " on rank " << least.rank << "\n";
  return out.str();
}

// In the processes mpirun starts from this binary (below), each rank writes
// its report and the process ends before any test runs.
const bool kReportedOnRanks = [] {
  const char* directory = std::getenv(kRanksDirectory);
  if (directory == nullptr) return false;
  start_world();
  const int rank = world_rank();
  std::string report = rank_report();
  const int code = end_after_error("every rank failed alike", 3);  // ends MPI
  report += "end after error: " + std::to_string(code) + ", ranks now " + std::to_string(world_size()) + "\n";
  std::ofstream(std::string(directory) + "/rank" + std::to_string(rank) + ".txt") << report;
  std::_Exit(0);
}();

bool launcher_environment() {
  for (const char* name : kLauncherVariables)
    if (std::getenv(name)) return true;
  return false;
}

TEST(MpiWorld, WithoutALauncherAProcessIsOneRank) {
  if (launcher_environment()) GTEST_SKIP() << "these tests run under a launcher";
  EXPECT_FALSE(launched_by_mpirun());
  start_world();  // nothing to start
  EXPECT_EQ(world_rank(), 0);
  EXPECT_EQ(world_size(), 1);
  finish_world();
  finish_world();  // safe when nothing was started
  EXPECT_EQ(world_size(), 1);
}

TEST(MpiWorld, TheLaunchersEnvironmentIsRecognised) {
  if (launcher_environment()) GTEST_SKIP() << "these tests run under a launcher";
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    ::setenv(name, "2", 1);
    EXPECT_TRUE(launched_by_mpirun()) << name;
    ::unsetenv(name);
  }
  EXPECT_FALSE(launched_by_mpirun());
}

TEST(MpiWorld, OnOneRankCollectivesGiveBackTheirValues) {
  if (launcher_environment()) GTEST_SKIP() << "these tests run under a launcher";
  std::vector<double> values{1.5, -2.0};
  sum_over_ranks(values);
  EXPECT_EQ(values, (std::vector<double>{1.5, -2.0}));
  EXPECT_EQ(sum_over_ranks(0.25), 0.25);
  EXPECT_EQ(max_over_ranks(-3.0), -3.0);
  EXPECT_EQ(gather_to_root(4.0), (std::vector<double>{4.0}));
  std::vector<int> ints{1, 2};
  broadcast_from_root(ints);
  EXPECT_EQ(ints, (std::vector<int>{1, 2}));
  std::vector<char> bytes{'a', 'b'};
  broadcast_bytes_from_root(bytes);
  broadcast_bytes_from(0, bytes);
  EXPECT_EQ(text(bytes), "ab");
  const RankedValue least = min_over_ranks(7);
  EXPECT_EQ(least.value, 7);
  EXPECT_EQ(least.rank, 0);
  std::vector<std::vector<double>> receive;
  exchange_with_neighbours({}, {}, receive);
  EXPECT_TRUE(receive.empty());
}

TEST(MpiWorld, OnOneRankTheExitAfterAnErrorPrintsItAndReturnsTheCode) {
  if (launcher_environment()) GTEST_SKIP() << "these tests run under a launcher";
  ::testing::internal::CaptureStderr();
  const int code = end_after_error("scene.yaml:3: bad key", 2);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "scene.yaml:3: bad key\n");
  EXPECT_EQ(code, 2);
}

TEST(MpiWorld, OnThreeRanksEveryCollectiveReachesEveryRank) {
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
  // Rank 0 alone says what every rank met.
  EXPECT_EQ(result.output.find("every rank failed alike"), result.output.rfind("every rank failed alike"))
      << result.output;
  EXPECT_NE(result.output.find("every rank failed alike\n"), std::string::npos) << result.output;
  const std::string shared =
      "ranks: 3\n"
      "sum: 4.5\n"
      "sum in place: 1 2 3\n"
      "max: 10\n";
  const std::string after_gather =
      "broadcast: 7 8 9\n"
      "bytes from root: hello\n"
      "bytes from rank 2: two\n";
  const std::string expected[3] = {
      shared + "gathered: 0 10 20\n" + after_gather + "from rank 1: 100 -1; from rank 2: 200\n",
      shared + "gathered:\n" + after_gather + "received: for 1\nfrom rank 2: 201 -1; from rank 0: 1\n",
      shared + "gathered:\n" + after_gather + "received: rank two\nfrom rank 0: 2 -1; from rank 1: 102\n",
  };
  for (int rank = 0; rank < 3; ++rank)
    EXPECT_EQ(test_support::read_file(dir.file("rank" + std::to_string(rank) + ".txt")),
              expected[rank] + "min: 3 on rank 1\nend after error: 3, ranks now 1\n")
        << "rank " << rank;
}

}  // namespace
}  // namespace tensormass::parallel
