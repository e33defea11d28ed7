// A SparseMatrix seen by CHOLMOD without a copy (internal header).
#ifndef TENSORMASS_LINEAR_SOLVERS_CHOLMOD_VIEW_HPP
#define TENSORMASS_LINEAR_SOLVERS_CHOLMOD_VIEW_HPP

#include <cholmod.h>

#include <span>

#include "tensormass/assembly/sparse_matrix.hpp"

namespace tensormass::detail {

/// A's lower triangle as CHOLMOD reads it. A stores both triangles; as
/// compressed columns it is the same (symmetric) matrix, and stype = -1
/// makes CHOLMOD ignore the upper part. Valid while A is.
inline cholmod_sparse cholmod_view_of(const SparseMatrix& A) {
  cholmod_sparse view{};
  view.nrow = view.ncol = static_cast<std::size_t>(A.rows);
  view.nzmax = A.values.size();
  view.p = const_cast<int*>(A.row_start.data());
  view.i = const_cast<int*>(A.columns.data());
  view.x = const_cast<double*>(A.values.data());
  view.stype = -1;
  view.itype = CHOLMOD_INT;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 1;
  view.packed = 1;
  return view;
}

/// b as a one-column dense matrix CHOLMOD reads. Valid while b is.
inline cholmod_dense cholmod_view_of(std::span<const double> b) {
  cholmod_dense view{};
  view.nrow = view.nzmax = view.d = b.size();
  view.ncol = 1;
  view.x = const_cast<double*>(b.data());
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  return view;
}

}  // namespace tensormass::detail

#endif
