/// \file sparse_matrix.hpp
/// A symmetric sparse matrix over the free degrees of freedom in compressed
/// rows (CSR) with both triangles stored, and deterministic parallel
/// vector kernels (results do not depend on the thread count).
#ifndef TENSORMASS_SPARSE_MATRIX_HPP
#define TENSORMASS_SPARSE_MATRIX_HPP

#include <cmath>
#include <span>
#include <vector>

namespace tensormass {

struct SparseMatrix {
  int rows = 0;
  std::vector<int> row_start;  ///< rows+1
  std::vector<int> columns;    ///< non-zeros, sorted within each row
  std::vector<double> values;  ///< non-zeros
  std::vector<int> diagonal;   ///< rows: position of (i, i) in values

  int nonzeros() const { return static_cast<int>(values.size()); }
  /// y = A x (parallel over rows).
  void multiply(std::span<const double> x, std::span<double> y) const;
};

/// Dot product summed in fixed chunks, so the result is the same for any thread count.
double dot(std::span<const double> a, std::span<const double> b);
inline double norm(std::span<const double> a) { return std::sqrt(dot(a, a)); }

}  // namespace tensormass

#endif
