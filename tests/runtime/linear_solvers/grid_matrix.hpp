// SPD test matrices with a 3D pattern, large enough for CHOLMOD to build a
// supernodal factor, that factor, and a small tridiagonal one (the linear
// solvers' tests share them).
#ifndef TENSORMASS_TESTS_LINEAR_SOLVERS_GRID_MATRIX_HPP
#define TENSORMASS_TESTS_LINEAR_SOLVERS_GRID_MATRIX_HPP

#include <cholmod.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "linear_solvers/cholmod_view.hpp"
#include "tensormass/assembly/sparse_matrix.hpp"

namespace tensormass::testing {

/// The 7-point Laplacian of a side^3 grid plus `shift` on the diagonal,
/// both triangles stored; row = (z * side + y) * side + x.
inline SparseMatrix grid_laplacian(int side, double shift) {
  SparseMatrix A;
  A.rows = side * side * side;
  A.row_start.push_back(0);
  for (int z = 0; z < side; ++z)
    for (int y = 0; y < side; ++y)
      for (int x = 0; x < side; ++x) {
        const int row = (z * side + y) * side + x;
        const int neighbours[7] = {row - side * side, row - side, row - 1, row, row + 1, row + side, row + side * side};
        const bool inside[7] = {z > 0, y > 0, x > 0, true, x + 1 < side, y + 1 < side, z + 1 < side};
        for (int k = 0; k < 7; ++k) {
          if (!inside[k]) continue;
          if (k == 3) A.diagonal.push_back(static_cast<int>(A.values.size()));
          A.columns.push_back(neighbours[k]);
          A.values.push_back(k == 3 ? 6.0 + shift : -1.0);
        }
        A.row_start.push_back(static_cast<int>(A.columns.size()));
      }
  return A;
}

/// The grid rows with x, y and z all in [first, first + width), ascending.
inline std::vector<int> cube_rows(int side, int first, int width) {
  std::vector<int> rows;
  for (int z = first; z < first + width; ++z)
    for (int y = first; y < first + width; ++y)
      for (int x = first; x < first + width; ++x) rows.push_back((z * side + y) * side + x);
  return rows;
}

/// The grid rows with x, y and z all below `corner`: a local block.
inline std::vector<int> corner_rows(int side, int corner) { return cube_rows(side, 0, corner); }

/// The grid rows of the cube of side `width` at the grid's centre: where
/// nested dissection puts its first separators.
inline std::vector<int> centre_rows(int side, int width) { return cube_rows(side, (side - width) / 2, width); }

/// A with `extra` times the Laplacian among `rows` (sorted) added: stiffer
/// there, still symmetric positive definite, unchanged elsewhere.
inline SparseMatrix stiffened(SparseMatrix A, const std::vector<int>& rows, double extra) {
  std::vector<char> in(A.rows, 0);
  for (int row : rows) in[row] = 1;
  for (int row : rows)
    for (int k = A.row_start[row]; k < A.row_start[row + 1]; ++k) {
      const int column = A.columns[k];
      if (column == row) A.values[k] += extra * 2.0;
      else if (in[column]) A.values[k] -= extra, A.values[A.diagonal[row]] += extra;
    }
  return A;
}

/// CHOLMOD's factor of A: supernodal LL^T, or the kind `supernodal` names;
/// in CHOLMOD's own ordering, or in `perm` (CHOLMOD's convention) postordered.
class CholmodFactor {
 public:
  explicit CholmodFactor(const SparseMatrix& A, int supernodal = CHOLMOD_SUPERNODAL,
                         const std::vector<int>& perm = {}) {
    cholmod_start(&common_);
    common_.supernodal = supernodal;
    common_.final_ll = 1;
    if (!perm.empty()) common_.nmethods = 1, common_.method[0].ordering = CHOLMOD_GIVEN;
    cholmod_sparse view = detail::cholmod_view_of(A);
    factor_ = cholmod_analyze_p(&view, perm.empty() ? nullptr : const_cast<int*>(perm.data()), nullptr, 0, &common_);
    if (!factor_ || !cholmod_factorize(&view, factor_, &common_) || factor_->minor < factor_->n)
      throw std::runtime_error("test factorisation failed");
  }
  ~CholmodFactor() {
    cholmod_free_factor(&factor_, &common_);
    cholmod_finish(&common_);
  }
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  const cholmod_factor& factor() const { return *factor_; }
  /// A^-1 b by CHOLMOD's own solve.
  std::vector<double> solve(const std::vector<double>& b) {
    cholmod_dense rhs = detail::cholmod_view_of(std::span<const double>(b));
    cholmod_dense* x = cholmod_solve(CHOLMOD_A, factor_, &rhs, &common_);
    const double* values = static_cast<const double*>(x->x);
    std::vector<double> result(values, values + b.size());
    cholmod_free_dense(&x, &common_);
    return result;
  }

 private:
  cholmod_common common_{};
  cholmod_factor* factor_ = nullptr;
};

/// |b - A x| / |b|.
inline double relative_residual(const SparseMatrix& A, const std::vector<double>& b, const std::vector<double>& x) {
  std::vector<double> ax(b.size());
  A.multiply(x, ax);
  double r2 = 0, b2 = 0;
  for (std::size_t i = 0; i < b.size(); ++i) r2 += (b[i] - ax[i]) * (b[i] - ax[i]), b2 += b[i] * b[i];
  return std::sqrt(r2 / b2);
}

/// A right-hand side with no symmetry.
inline std::vector<double> uneven_vector(int n) {
  std::vector<double> b(n);
  for (int i = 0; i < n; ++i) b[i] = std::sin(0.37 * i) + 0.5;
  return b;
}

/// The n x n matrix tridiag(-1, 2 + shift, -1), both triangles stored.
inline SparseMatrix laplacian(int n, double shift) {
  SparseMatrix A;
  A.rows = n;
  A.row_start.push_back(0);
  for (int i = 0; i < n; ++i) {
    for (int j = i - 1; j <= i + 1; ++j) {
      if (j < 0 || j >= n) continue;
      if (j == i) A.diagonal.push_back(static_cast<int>(A.values.size()));
      A.columns.push_back(j);
      A.values.push_back(j == i ? 2.0 + shift : -1.0);
    }
    A.row_start.push_back(static_cast<int>(A.columns.size()));
  }
  return A;
}

inline std::vector<double> right_hand_side(int n) {
  std::vector<double> b(n);
  for (int i = 0; i < n; ++i) b[i] = std::sin(0.1 * i) + 1.0;
  return b;
}

}  // namespace tensormass::testing

#endif
