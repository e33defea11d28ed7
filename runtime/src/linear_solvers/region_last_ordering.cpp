#include "linear_solvers/region_last_ordering.hpp"

#include <string>

#include "linear_solvers/cholmod_view.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::detail {

std::vector<int> dilated_rows(const SparseMatrix& A, std::span<const int> rows, int rings) {
  std::vector<char> in(A.rows, 0);
  std::vector<int> front(rows.begin(), rows.end()), next;
  for (int row : rows) in[row] = 1;
  for (int ring = 0; ring < rings; ++ring, front.swap(next)) {
    next.clear();
    for (int row : front)
      for (int k = A.row_start[row]; k < A.row_start[row + 1]; ++k)
        if (const int column = A.columns[k]; !in[column]) in[column] = 1, next.push_back(column);
  }
  std::vector<int> dilated;
  for (int row = 0; row < A.rows; ++row)
    if (in[row]) dilated.push_back(row);
  return dilated;
}

namespace {

/// The rows with membership[row] == part, ordered by METIS on their graph,
/// appended to `perm`.
void append_part_ordering(const SparseMatrix& A, const std::vector<char>& membership, char part, cholmod_common& common,
                          std::vector<int>& perm) {
  std::vector<int> rows, local(A.rows, -1);
  for (int row = 0; row < A.rows; ++row)
    if (membership[row] == part) local[row] = static_cast<int>(rows.size()), rows.push_back(row);
  const int m = static_cast<int>(rows.size());
  if (m <= 1) {
    perm.insert(perm.end(), rows.begin(), rows.end());
    return;
  }
  // The part's graph as a symmetric matrix (both triangles, ones).
  SparseMatrix graph;
  graph.rows = m;
  graph.row_start.assign(1, 0);
  for (int row : rows) {
    for (int k = A.row_start[row]; k < A.row_start[row + 1]; ++k)
      if (const int column = local[A.columns[k]]; column >= 0) graph.columns.push_back(column);
    graph.row_start.push_back(static_cast<int>(graph.columns.size()));
  }
  graph.values.assign(graph.columns.size(), 1.0);
  cholmod_sparse view = cholmod_view_of(graph);
  std::vector<int> order(m);
  if (!cholmod_metis(&view, nullptr, 0, /*postorder=*/0, order.data(), &common))
    throw NumericalError("METIS could not order " + std::to_string(m) + " rows of the stiffness matrix (status " +
                         std::to_string(common.status) + ")");
  for (int k : order) perm.push_back(rows[k]);
}

}  // namespace

std::vector<int> region_last_ordering(const SparseMatrix& A, std::span<const int> region, cholmod_common& common) {
  std::vector<char> membership(A.rows, 0);
  for (int row : region) membership[row] = 1;
  std::vector<int> perm;
  perm.reserve(A.rows);
  append_part_ordering(A, membership, 0, common, perm);
  append_part_ordering(A, membership, 1, common, perm);
  return perm;
}

}  // namespace tensormass::detail
