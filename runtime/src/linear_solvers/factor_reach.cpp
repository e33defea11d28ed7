#include "linear_solvers/factor_reach.hpp"

#include <algorithm>

#include "tensormass/common/errors.hpp"

namespace tensormass::detail {

FactorReach::FactorReach(const cholmod_factor& factor)
    : factor_(&factor),
      super_(static_cast<const int*>(factor.super)),
      pi_(static_cast<const int*>(factor.pi)),
      px_(static_cast<const int*>(factor.px)),
      s_(static_cast<const int*>(factor.s)) {
  if (!factor.is_super || !factor.is_ll || factor.xtype != CHOLMOD_REAL || factor.itype != CHOLMOD_INT ||
      factor.dtype != CHOLMOD_DOUBLE)
    throw NumericalError("restricted substitutions need a numeric supernodal LL^T factor");
  const int n = static_cast<int>(factor.n), supernodes = static_cast<int>(factor.nsuper);
  const int* perm = static_cast<const int*>(factor.Perm);
  permutation_.resize(n);
  position_.resize(n);
  for (int k = 0; k < n; ++k) permutation_[k] = perm ? perm[k] : k;
  for (int k = 0; k < n; ++k) position_[permutation_[k]] = k;
  supernode_of_column_.resize(n);
  for (int s = 0; s < supernodes; ++s)
    std::fill(supernode_of_column_.begin() + super_[s], supernode_of_column_.begin() + super_[s + 1], s);
  parent_.assign(supernodes, -1);
  std::size_t widest = 0;
  for (int s = 0; s < supernodes; ++s) {
    const int columns = super_[s + 1] - super_[s], rows = pi_[s + 1] - pi_[s];
    // The first row below the diagonal block is the parent's column.
    if (rows > columns) parent_[s] = supernode_of_column_[s_[pi_[s] + columns]];
    if (parent_[s] >= 0 && parent_[s] <= s) throw NumericalError("the factor's supernodes are not in tree order");
    widest = std::max(widest, static_cast<std::size_t>(rows));
  }
  buffer_.resize(widest);
  marked_.assign(supernodes, 0);
}

double FactorReach::select(std::span<const int> rows) {
  std::fill(marked_.begin(), marked_.end(), 0);
  for (int row : rows)
    for (int s = supernode_of_column_[position_[row]]; s >= 0 && !marked_[s]; s = parent_[s]) marked_[s] = 1;
  selected_.clear();
  double all = 0.0, reached = 0.0;
  for (int s = 0; s < static_cast<int>(marked_.size()); ++s) {
    const double entries = double(super_[s + 1] - super_[s]) * double(pi_[s + 1] - pi_[s]);
    all += entries;
    if (marked_[s]) selected_.push_back(s), reached += entries;
  }
  return all > 0.0 ? reached / all : 0.0;
}

void FactorReach::permute(std::span<const double> b, std::span<double> v) const {
  for (std::size_t k = 0; k < permutation_.size(); ++k) v[k] = b[permutation_[k]];
}

void FactorReach::unpermute(std::span<const double> v, std::span<double> x) const {
  for (std::size_t k = 0; k < permutation_.size(); ++k) x[permutation_[k]] = v[k];
}

void FactorReach::clear_selected(std::span<double> v) const {
  for (int s : selected_) std::fill(v.begin() + super_[s], v.begin() + super_[s + 1], 0.0);
}

void FactorReach::forward(std::span<double> v, bool selected_only) const {
  if (selected_only)
    for (int s : selected_) forward_supernode(s, v);
  else
    for (int s = 0; s < static_cast<int>(parent_.size()); ++s) forward_supernode(s, v);
}

void FactorReach::backward(std::span<double> v, bool selected_only) const {
  if (selected_only)
    for (auto s = selected_.rbegin(); s != selected_.rend(); ++s) backward_supernode(*s, v);
  else
    for (int s = static_cast<int>(parent_.size()) - 1; s >= 0; --s) backward_supernode(s, v);
}

// A supernode holds columns [c0, c0 + columns) of L as a dense column-major
// block of `rows` rows: the lower triangle of its diagonal block, then the
// rows below it, whose sums go to ancestors' columns (s_ names all rows,
// its own columns first). Each substitution copies the supernode's part of
// v into buffer_, so that every column is one contiguous vector loop.
void FactorReach::forward_supernode(int s, std::span<double> v) const {
  const int c0 = super_[s], columns = super_[s + 1] - c0, rows = pi_[s + 1] - pi_[s];
  const double* block = static_cast<const double*>(factor_->x) + px_[s];
  const int* row_of = s_ + pi_[s];
  double* local = buffer_.data();
  std::copy_n(v.data() + c0, columns, local);
  std::fill(local + columns, local + rows, 0.0);
  for (int j = 0; j < columns; ++j) {
    const double* column = block + static_cast<std::ptrdiff_t>(j) * rows;
    const double y = local[j] /= column[j];
#pragma omp simd
    for (int i = j + 1; i < rows; ++i) local[i] -= column[i] * y;
  }
  std::copy_n(local, columns, v.data() + c0);
  for (int i = columns; i < rows; ++i) v[row_of[i]] += local[i];
}

void FactorReach::backward_supernode(int s, std::span<double> v) const {
  const int c0 = super_[s], columns = super_[s + 1] - c0, rows = pi_[s + 1] - pi_[s];
  const double* block = static_cast<const double*>(factor_->x) + px_[s];
  const int* row_of = s_ + pi_[s];
  double* local = buffer_.data();  // its columns, then the ancestors' solution
  for (int i = 0; i < rows; ++i) local[i] = v[row_of[i]];
  for (int j = columns - 1; j >= 0; --j) {
    const double* column = block + static_cast<std::ptrdiff_t>(j) * rows;
    double sum = 0.0;
#pragma omp simd reduction(+ : sum)
    for (int i = j + 1; i < rows; ++i) sum += column[i] * local[i];
    local[j] = (local[j] - sum) / column[j];
  }
  std::copy_n(local, columns, v.data() + c0);
}

}  // namespace tensormass::detail
