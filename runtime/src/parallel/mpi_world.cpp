// MPI through PETSc: PetscInitialize starts MPI when the launcher's
// environment says this process is one of several ranks.
#include "tensormass/parallel/mpi_world.hpp"

#include <mpi.h>
#include <omp.h>
#include <petscsys.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "parallel/petsc_start.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::parallel {

namespace {
bool started_here = false;        // MPI's world, by start_world()
bool petsc_started_here = false;  // PETSc, by its first user (a serial run's PETSc solver too)

/// OpenMP threads per rank when the user set none: the cores of this
/// machine shared among its ranks (mpirun binds each of 2 ranks on 2 cores
/// to one core; 3 ranks with --oversubscribe get one thread each).
void share_cores_among_local_ranks() {
  if (std::getenv("OMP_NUM_THREADS")) return;
  MPI_Comm local;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &local);
  int local_ranks = 1;
  MPI_Comm_size(local, &local_ranks);
  MPI_Comm_free(&local);
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  omp_set_num_threads(std::max(1, std::min(omp_get_num_procs(), cores / local_ranks)));
}

bool mpi_running() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  return initialized && !finalized;
}
}  // namespace

namespace detail {
void ensure_petsc_started() {
  static std::once_flag once;
  std::call_once(once, [] {
    PetscBool started = PETSC_FALSE;
    PetscInitialized(&started);
    if (!started && PetscInitializeNoArguments() != 0) throw NumericalError("PETSc (and MPI) failed to start");
    petsc_started_here = !started;
    // PETSc's own traceback on stderr when asked (debugging a PETSc option).
    if (!std::getenv("TENSORMASS_PETSC_TRACEBACK")) PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  });
}
}  // namespace detail

bool launched_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

void start_world() {
  if (!launched_by_mpirun() || mpi_running()) return;
  detail::ensure_petsc_started();
  started_here = true;
  share_cores_among_local_ranks();
}

void finish_world() {
  // PETSc's finalisation prints what PETSC_OPTIONS asked for (-log_view),
  // on one process as on several.
  if (petsc_started_here) {
    petsc_started_here = false;
    PetscFinalize();
  }
  if (!started_here) return;
  started_here = false;
  if (mpi_running()) MPI_Finalize();
}

int world_rank() {
  if (!mpi_running()) return 0;
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

int world_size() {
  if (!mpi_running()) return 1;
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

void sum_over_ranks(std::span<double> values) {
  // Used on vectors with one non-zero contribution per entry (Distribution),
  // whose sums are exact in any order: every rank gets the same bits.
  if (world_size() == 1 || values.empty()) return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
}

double sum_over_ranks(double value) {
  // Summed on rank 0 in rank order and sent to all: the same bits everywhere.
  if (world_size() == 1) return value;
  double total = 0.0;
  MPI_Reduce(&value, &total, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
  MPI_Bcast(&total, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  return total;
}

double max_over_ranks(double value) {
  if (world_size() == 1) return value;
  double largest = value;
  MPI_Allreduce(&value, &largest, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return largest;
}

void exchange_with_neighbours(std::span<const int> neighbours, const std::vector<std::vector<double>>& send,
                              std::vector<std::vector<double>>& receive) {
  if (send.size() != neighbours.size() || receive.size() != neighbours.size())
    throw std::invalid_argument("exchange_with_neighbours: one buffer per neighbour each way");
  if (neighbours.empty()) return;
  constexpr int kTag = 4242;
  std::vector<MPI_Request> requests(2 * neighbours.size());
  for (std::size_t i = 0; i < neighbours.size(); ++i)
    MPI_Irecv(receive[i].data(), static_cast<int>(receive[i].size()), MPI_DOUBLE, neighbours[i], kTag, MPI_COMM_WORLD,
              &requests[i]);
  for (std::size_t i = 0; i < neighbours.size(); ++i)
    MPI_Isend(send[i].data(), static_cast<int>(send[i].size()), MPI_DOUBLE, neighbours[i], kTag, MPI_COMM_WORLD,
              &requests[neighbours.size() + i]);
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
}

std::vector<double> gather_to_root(double value) {
  if (world_size() == 1) return {value};
  std::vector<double> values(world_rank() == 0 ? world_size() : 0);
  MPI_Gather(&value, 1, MPI_DOUBLE, values.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  return values;
}

void broadcast_from_root(std::span<int> values) {
  if (world_size() == 1 || values.empty()) return;
  MPI_Bcast(values.data(), static_cast<int>(values.size()), MPI_INT, 0, MPI_COMM_WORLD);
}

void broadcast_bytes_from_root(std::vector<char>& bytes) { broadcast_bytes_from(0, bytes); }

namespace {
constexpr std::uint64_t kPiece = std::uint64_t{1} << 30;  // MPI counts are ints
constexpr int kBytesTag = 7101;
}  // namespace

void broadcast_bytes_from(int root, std::vector<char>& bytes) {
  if (world_size() == 1) return;
  std::uint64_t size = bytes.size();
  MPI_Bcast(&size, 1, MPI_UINT64_T, root, MPI_COMM_WORLD);
  bytes.resize(size);
  for (std::uint64_t at = 0; at < size; at += kPiece)
    MPI_Bcast(bytes.data() + at, static_cast<int>(std::min(kPiece, size - at)), MPI_CHAR, root, MPI_COMM_WORLD);
}

void send_bytes_from_root(int to, const std::vector<char>& bytes) {
  std::uint64_t size = bytes.size();
  MPI_Send(&size, 1, MPI_UINT64_T, to, kBytesTag, MPI_COMM_WORLD);
  for (std::uint64_t at = 0; at < size; at += kPiece)
    MPI_Send(bytes.data() + at, static_cast<int>(std::min(kPiece, size - at)), MPI_CHAR, to, kBytesTag, MPI_COMM_WORLD);
}

std::vector<char> receive_bytes_from_root() {
  std::uint64_t size = 0;
  MPI_Recv(&size, 1, MPI_UINT64_T, 0, kBytesTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  std::vector<char> bytes(size);
  for (std::uint64_t at = 0; at < size; at += kPiece)
    MPI_Recv(bytes.data() + at, static_cast<int>(std::min(kPiece, size - at)), MPI_CHAR, 0, kBytesTag, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
  return bytes;
}

RankedValue min_over_ranks(int value) {
  if (world_size() == 1) return {value, 0};
  struct {
    int value, rank;
  } mine{value, world_rank()}, least{};
  MPI_Allreduce(&mine, &least, 1, MPI_2INT, MPI_MINLOC, MPI_COMM_WORLD);
  return {least.value, least.rank};
}

int end_after_error(const std::string& message, int exit_code) {
  if (world_size() == 1) {
    std::fprintf(stderr, "%s\n", message.c_str());
    return exit_code;
  }
  // Did every rank fail? A non-blocking barrier answers without hanging
  // when some rank is still computing (or waiting in another collective).
  MPI_Request request;
  MPI_Ibarrier(MPI_COMM_WORLD, &request);
  int all_arrived = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!all_arrived && std::chrono::steady_clock::now() < deadline) {
    MPI_Test(&request, &all_arrived, MPI_STATUS_IGNORE);
    if (!all_arrived) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (all_arrived) {
    if (world_rank() == 0) std::fprintf(stderr, "%s\n", message.c_str());
    finish_world();
    return exit_code;
  }
  std::fprintf(stderr, "%s (on MPI rank %d of %d; stopping every rank)\n", message.c_str(), world_rank(), world_size());
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, exit_code);
  return exit_code;
}

}  // namespace tensormass::parallel
