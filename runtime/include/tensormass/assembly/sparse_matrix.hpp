/// \file sparse_matrix.hpp
/// A symmetric sparse matrix over the free degrees of freedom in compressed
/// rows (CSR) with both triangles stored, and deterministic parallel
/// vector kernels (results do not depend on the thread count).
#ifndef TENSORMASS_SPARSE_MATRIX_HPP
#define TENSORMASS_SPARSE_MATRIX_HPP

#include <cmath>
#include <memory>
#include <span>
#include <vector>

namespace tensormass {

/// The node-block structure of a tangent's pattern over the free dofs. A
/// node's free dofs are consecutive rows with one column list, and that
/// list is runs of consecutive columns, one run per neighbour node (its
/// free dofs, 1 to d of them). Kept once per node, it stands for the
/// column indices of d rows and up to d columns each: a product reads
/// about 8.5 bytes per non-zero instead of 12.
struct NodeRuns {
  std::vector<int> node_row_start;  ///< nodes+1: the node's first free row (rows of a node are consecutive)
  std::vector<int> run_start;       ///< nodes+1: the node's runs in run_column
  std::vector<int> run_column;      ///< runs: first column
  /// nodes: d when every run of the node has d columns (the usual case, a
  /// product unrolled for it), else 0 (the node's rows go row by row)
  std::vector<unsigned char> full;
};

struct SparseMatrix {
  int rows = 0;
  std::vector<int> row_start;  ///< rows+1
  std::vector<int> columns;    ///< non-zeros, sorted within each row
  std::vector<double> values;  ///< non-zeros
  std::vector<int> diagonal;   ///< rows: position of (i, i) in values
  /// The pattern's node blocks (Assembler::pattern() sets them; shared by
  /// its copies), or null. Whoever changes row_start or columns must reset it.
  std::shared_ptr<const NodeRuns> node_runs;

  int nonzeros() const { return static_cast<int>(values.size()); }
  /// y = A x (parallel over rows; by node blocks when node_runs is set,
  /// their sums in another fixed order: equal to multiply_by_rows up to
  /// rounding, the same bits on any number of threads).
  void multiply(std::span<const double> x, std::span<double> y) const;
  /// y = A x row by row from the column indices (what multiply() does
  /// without node_runs).
  void multiply_by_rows(std::span<const double> x, std::span<double> y) const;
};

/// Dot product summed in fixed chunks, so the result is the same for any thread count.
double dot(std::span<const double> a, std::span<const double> b);
inline double norm(std::span<const double> a) { return std::sqrt(dot(a, a)); }

}  // namespace tensormass

#endif
