// A build without PETSc (and so without MPI): one rank.
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "tensormass/common/errors.hpp"
#include "tensormass/parallel/cell_partition.hpp"
#include "tensormass/parallel/mpi_world.hpp"

namespace tensormass::parallel {

/// Only a launch on several ranks matters here (one rank runs as usual): a
/// world size above 1, or a rank above 0 where a launcher (PMIx) gives no size.
bool launched_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* value = std::getenv(name); value && std::atoi(value) > 1) return true;
  for (const char* name : {"PMIX_RANK", "PMI_RANK"})
    if (const char* value = std::getenv(name); value && std::atoi(value) > 0) return true;
  return false;
}

void start_world() {
  if (launched_by_mpirun())
    throw InputError(
        "launched by mpirun on several ranks, but this build has no MPI (apt-get install libpetsc-real-dev "
        "libopenmpi-dev, then build again)");
}
void finish_world() {}
int world_rank() { return 0; }
int world_size() { return 1; }
void sum_over_ranks(std::span<double>) {}
double sum_over_ranks(double value) { return value; }
double max_over_ranks(double value) { return value; }
void exchange_with_neighbours(std::span<const int> neighbours, const std::vector<std::vector<double>>&,
                              std::vector<std::vector<double>>&) {
  if (!neighbours.empty()) throw std::logic_error("exchange_with_neighbours: one rank, no neighbours");
}
std::vector<double> gather_to_root(double value) { return {value}; }
void broadcast_from_root(std::span<int>) {}
void broadcast_bytes_from_root(std::vector<char>&) {}
void broadcast_bytes_from(int, std::vector<char>&) {}
void send_bytes_from_root(int, const std::vector<char>&) {
  throw std::logic_error("send_bytes_from_root: one rank, nobody to send to");
}
std::vector<char> receive_bytes_from_root() {
  throw std::logic_error("receive_bytes_from_root: one rank, nobody sends");
}
RankedValue min_over_ranks(int value) { return {value, 0}; }
int end_after_error(const std::string& message, int exit_code) {
  std::fprintf(stderr, "%s\n", message.c_str());
  return exit_code;
}

std::vector<int> partition_cells(const Mesh& mesh, int parts) {
  if (parts > 1) throw InputError("cutting the mesh for MPI ranks needs PETSc, which this build lacks");
  return std::vector<int>(mesh.cell_count(), 0);
}

}  // namespace tensormass::parallel
