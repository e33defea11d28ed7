/// \file mpi_world.hpp
/// The MPI ranks a run spans. A process started by mpirun (or mpiexec)
/// starts MPI, through PETSc, in start_world(); any other process stays
/// one rank and never loads MPI's machinery. Every function works on one
/// rank, in builds with or without PETSc.
#ifndef TENSORMASS_PARALLEL_MPI_WORLD_HPP
#define TENSORMASS_PARALLEL_MPI_WORLD_HPP

#include <span>
#include <string>
#include <vector>

namespace tensormass::parallel {

/// True when a launcher's environment is present (Open MPI, PMIx or PMI);
/// in a build without MPI, only one of several ranks (mpirun -n 1 runs as usual).
bool launched_by_mpirun();
/// Starts MPI when launched_by_mpirun(); call once at program start. Unless
/// OMP_NUM_THREADS is set, each rank then runs the machine's cores divided
/// by the ranks on it as OpenMP threads (solver.threads still overrides).
/// Throws InputError when launched on several ranks by a build without PETSc.
void start_world();
/// Ends what start_world started (MPI and PETSc); safe to call when nothing was started.
void finish_world();
/// This process's rank (0 unless started) and the number of ranks (1 unless started).
int world_rank();
int world_size();
/// In-place sums over all ranks, the same bits on every rank (a no-op on one rank).
void sum_over_ranks(std::span<double> values);
double sum_over_ranks(double value);
/// The largest `value` over the ranks, on every rank.
double max_over_ranks(double value);
/// Point-to-point exchange with the ranks in `neighbours` (not this one):
/// sends send[i] to neighbours[i] and receives receive[i] from it. The
/// caller sizes receive[i] (each side knows what the other sends); every
/// neighbour must call it with this rank among its neighbours.
void exchange_with_neighbours(std::span<const int> neighbours, const std::vector<std::vector<double>>& send,
                              std::vector<std::vector<double>>& receive);
/// Every rank's `value`, in rank order, on rank 0 (other ranks get an empty vector).
std::vector<double> gather_to_root(double value);
/// Rank 0's values, sent to every rank (a no-op on one rank).
void broadcast_from_root(std::span<int> values);
/// Rank 0's bytes, sent to every rank: the others' `bytes` are resized to
/// rank 0's length (any length: sent in pieces of at most 1 GiB).
void broadcast_bytes_from_root(std::vector<char>& bytes);
/// `root`'s bytes, sent to every rank, as broadcast_bytes_from_root.
void broadcast_bytes_from(int root, std::vector<char>& bytes);
/// Rank 0 sends `bytes` to rank `to` (1 .. world_size()-1), which takes them
/// with receive_bytes_from_root(); any length, in pieces of at most 1 GiB.
void send_bytes_from_root(int to, const std::vector<char>& bytes);
std::vector<char> receive_bytes_from_root();
/// The smallest `value` over the ranks and the lowest rank holding it, on every rank.
struct RankedValue {
  int value = 0;
  int rank = 0;
};
RankedValue min_over_ranks(int value);
/// The exit after an error caught on this rank: when every rank caught one
/// (a bad scene, a numerical failure: the ranks hold the same state), rank 0
/// prints `message` and all return `exit_code`; when the others do not
/// arrive within a few seconds, this rank prints it with its number and
/// aborts every rank with `exit_code` (nothing hangs). One rank: prints, returns.
int end_after_error(const std::string& message, int exit_code);

}  // namespace tensormass::parallel

#endif
