/// \file distribution.hpp
/// How a model's work is shared among MPI ranks. Every rank holds the whole
/// mesh and state (replicated); each owns the cells of its part and the
/// nodes whose lowest-ranked cell is its own. A rank assembles every cell
/// that touches one of its nodes, so its rows (its nodes' dofs) of the
/// forces and of the tangent are complete with no communication; other
/// rows are partial and are never read: complete_* keep a rank's own rows
/// and sum over ranks. The linear solver numbers the free dofs rank by rank
/// (global_row) so that each rank's rows are one contiguous range.
#ifndef TENSORMASS_PARALLEL_DISTRIBUTION_HPP
#define TENSORMASS_PARALLEL_DISTRIBUTION_HPP

#include <span>
#include <vector>

#include "tensormass/model/model.hpp"

namespace tensormass {

class Distribution {
 public:
  /// cell_owner: the rank of every cell (cell_count, values in [0, size)).
  /// Throws std::invalid_argument on a wrong size or rank.
  Distribution(const Model& model, std::vector<int> cell_owner, int rank, int size);

  int rank() const { return rank_; }
  int size() const { return size_; }
  /// Cells of this rank's part: its energy terms and output piece.
  bool owns_cell(int cell) const { return cell_owner_[cell] == rank_; }
  int cell_owner(int cell) const { return cell_owner_[cell]; }
  /// Cells whose kernels this rank runs: its own and those touching its nodes.
  bool assembles_cell(int cell) const { return assembled_[cell] != 0; }
  int assembled_cell_count() const { return assembled_count_; }
  /// A node belongs to the lowest rank among its cells' owners (rank 0 for a node in no cell).
  bool owns_node(int node) const { return node_owner_[node] == rank_; }
  int node_owner(int node) const { return node_owner_[node]; }

  /// free_dof_count: each free dof's row in the rank-by-rank numbering.
  const std::vector<int>& global_row() const { return global_row_; }
  /// This rank's free dofs (free indices, ascending): global rows
  /// first_global_row() .. first_global_row() + size - 1, in this order.
  const std::vector<int>& owned_free_rows() const { return owned_free_rows_; }
  int first_global_row() const { return first_global_row_; }

  /// Zeroes the entries of other ranks' dofs: v is dof_count or free_dof_count long.
  void keep_own_dofs(std::span<double> v) const;
  void keep_own_free(std::span<double> v) const;
  /// keep_own_* then the sum over ranks: every rank gets the complete vector.
  void complete_dofs(std::span<double> v) const;
  void complete_free(std::span<double> v) const;

 private:
  const Model* model_;
  int rank_, size_;
  std::vector<int> cell_owner_, node_owner_;
  std::vector<char> assembled_;
  int assembled_count_ = 0;
  std::vector<int> global_row_, owned_free_rows_;
  int first_global_row_ = 0;
};

}  // namespace tensormass

#endif
