// Forward and back substitutions with a CHOLMOD supernodal factor, over
// all of it or over the supernodes a set of rows reaches (internal header).
#ifndef TENSORMASS_LINEAR_SOLVERS_FACTOR_REACH_HPP
#define TENSORMASS_LINEAR_SOLVERS_FACTOR_REACH_HPP

#include <cholmod.h>

#include <span>
#include <vector>

namespace tensormass::detail {

/// P A P^T = L L^T from CHOLMOD (supernodal, numeric, LL^T, int indices).
/// A right-hand side that is zero outside a set of rows N leaves L^-1 P b
/// zero outside the columns N reaches in the elimination tree (N's columns
/// and their ancestors), and (A^-1 b) on N needs L^-T only on those
/// columns: both substitutions can skip every other supernode. Vectors
/// here are in the factor's (permuted) order: v[k] belongs to row Perm[k].
/// The factor must outlive this object and keep its symbolic structure
/// (refactorising the same pattern keeps it; a new analysis does not).
class FactorReach {
 public:
  /// Throws NumericalError unless `factor` is supernodal, numeric and LL^T.
  explicit FactorReach(const cholmod_factor& factor);

  int rows() const { return static_cast<int>(permutation_.size()); }
  /// Where row `row` of A sits in the factor's order.
  int position(int row) const { return position_[row]; }
  /// Selects the supernodes the rows (A's numbering) reach; returns their
  /// share of L's stored entries (what a selected substitution reads).
  double select(std::span<const int> rows);
  /// v[k] = b[Perm[k]] for every k.
  void permute(std::span<const double> b, std::span<double> v) const;
  /// x[Perm[k]] = v[k] for every k.
  void unpermute(std::span<const double> v, std::span<double> x) const;
  /// Zeroes v on the selected supernodes' columns.
  void clear_selected(std::span<double> v) const;
  /// v := L^-1 v, in place, over every supernode or the selected ones
  /// (then v must be zero on the selected columns outside the rows given
  /// to select(); columns outside the selection are left as they are).
  void forward(std::span<double> v, bool selected_only) const;
  /// v := L^-T v, in place, over every supernode or the selected ones
  /// (the selected columns come out right whatever v holds elsewhere).
  void backward(std::span<double> v, bool selected_only) const;

 private:
  void forward_supernode(int s, std::span<double> v) const;
  void backward_supernode(int s, std::span<double> v) const;

  const cholmod_factor* factor_;
  const int* super_;  ///< nsuper + 1: each supernode's first column
  const int* pi_;     ///< nsuper + 1: where each supernode's rows start in s_
  const int* px_;     ///< nsuper + 1: where each supernode's values start (column-major, its rows by its columns)
  const int* s_;      ///< row indices, each supernode's own columns first
  std::vector<int> permutation_, position_;
  std::vector<int> parent_;  ///< supernodal elimination tree (-1: a root)
  std::vector<int> supernode_of_column_;
  std::vector<int> selected_;  ///< ascending
  std::vector<char> marked_;
  mutable std::vector<double> buffer_;  ///< one supernode's rows of v
};

}  // namespace tensormass::detail

#endif
