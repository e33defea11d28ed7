#include "tensormass/assembly/sparse_matrix.hpp"

#include <algorithm>

namespace tensormass {

namespace {
// Below these sizes a parallel region costs more than it saves (and much
// more on a machine whose cores are busy with other work).
constexpr int kParallelRows = 20000;
constexpr std::ptrdiff_t kParallelLength = 50000;

/// Row i of A x from the column indices.
inline double row_product(const SparseMatrix& A, int i, const double* x) {
  double sum = 0.0;
  for (int k = A.row_start[i]; k < A.row_start[i + 1]; ++k) sum += A.values[k] * x[A.columns[k]];
  return sum;
}

/// The rows of node n, every neighbour with all its R dofs free, one after
/// the other: the values read once and in order, the node's runs (a few
/// dozen bytes) read again from cache for each row. A row sums into R
/// partial sums, one per column of a run, so that R products are in flight
/// rather than one chain of additions (a sum in column order was 0.88 to
/// 0.91x the row product; this is 0.59 to 0.84x, bench runtime --only
/// spmv). The order is fixed, so the bits do not depend on the threads.
template <int R>
inline void multiply_node(const SparseMatrix& A, const NodeRuns& runs, int n, const double* x, double* y) {
  const int* run_column = runs.run_column.data();
  const int first_run = runs.run_start[n], last_run = runs.run_start[n + 1];
  for (int row = runs.node_row_start[n]; row < runs.node_row_start[n + 1]; ++row) {
    const double* v = A.values.data() + A.row_start[row];
    double sum[R] = {};
    for (int run = first_run; run < last_run; ++run, v += R) {
      const double* xs = x + run_column[run];
      for (int c = 0; c < R; ++c) sum[c] += v[c] * xs[c];
    }
    double total = sum[0];
    for (int c = 1; c < R; ++c) total += sum[c];
    y[row] = total;
  }
}

}  // namespace

void SparseMatrix::multiply_by_rows(std::span<const double> x, std::span<double> y) const {
#pragma omp parallel for schedule(static) if (rows >= kParallelRows)
  for (int i = 0; i < rows; ++i) y[i] = row_product(*this, i, x.data());
}

void SparseMatrix::multiply(std::span<const double> x, std::span<double> y) const {
  if (!node_runs) return multiply_by_rows(x, y);
  const NodeRuns& runs = *node_runs;
  const int nodes = static_cast<int>(runs.node_row_start.size()) - 1;
#pragma omp parallel for schedule(static) if (rows >= kParallelRows)
  for (int n = 0; n < nodes; ++n) {
    if (runs.full[n] == 3) {
      multiply_node<3>(*this, runs, n, x.data(), y.data());
    } else if (runs.full[n] == 2) {
      multiply_node<2>(*this, runs, n, x.data(), y.data());
    } else {  // a neighbour with some dofs fixed (near a constrained boundary): row by row
      for (int row = runs.node_row_start[n]; row < runs.node_row_start[n + 1]; ++row)
        y[row] = row_product(*this, row, x.data());
    }
  }
}

double dot(std::span<const double> a, std::span<const double> b) {
  // Fixed chunk boundaries and a sequential sum of the chunk results: the
  // rounding is the same whatever the number of threads.
  constexpr int kChunks = 64;
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(a.size());
  double partial[kChunks];
#pragma omp parallel for schedule(static) if (n >= kParallelLength)
  for (int chunk = 0; chunk < kChunks; ++chunk) {
    const std::ptrdiff_t begin = n * chunk / kChunks, end = n * (chunk + 1) / kChunks;
    double sum = 0.0;
    for (std::ptrdiff_t i = begin; i < end; ++i) sum += a[i] * b[i];
    partial[chunk] = sum;
  }
  double total = 0.0;
  for (double p : partial) total += p;
  return total;
}

}  // namespace tensormass
