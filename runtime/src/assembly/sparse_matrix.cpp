#include "tensormass/assembly/sparse_matrix.hpp"

#include <algorithm>

namespace tensormass {

namespace {
// Below these sizes a parallel region costs more than it saves (and much
// more on a machine whose cores are busy with other work).
constexpr int kParallelRows = 20000;
constexpr std::ptrdiff_t kParallelLength = 50000;
}  // namespace

void SparseMatrix::multiply(std::span<const double> x, std::span<double> y) const {
#pragma omp parallel for schedule(static) if (rows >= kParallelRows)
  for (int i = 0; i < rows; ++i) {
    double sum = 0.0;
    for (int k = row_start[i]; k < row_start[i + 1]; ++k) sum += values[k] * x[columns[k]];
    y[i] = sum;
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
