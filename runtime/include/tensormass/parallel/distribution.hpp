/// \file distribution.hpp
/// How a model's work is shared among MPI ranks. Every rank holds every
/// node and the whole state; its model holds either the whole mesh
/// (replicated) or its part of it (MeshPart: the cells it assembles). Each
/// rank owns the cells of its part of the cut and the nodes whose
/// lowest-ranked cell is its own. A rank assembles every cell that touches
/// one of its nodes, so its rows (its nodes' dofs) of the forces and of the
/// tangent are complete with no communication; other rows are partial and
/// are never read: complete_* keep a rank's own rows and sum over ranks.
/// The linear solver numbers the free dofs rank by rank (global_row) so
/// that each rank's rows are one contiguous range.
#ifndef TENSORMASS_PARALLEL_DISTRIBUTION_HPP
#define TENSORMASS_PARALLEL_DISTRIBUTION_HPP

#include <span>
#include <vector>

#include "tensormass/model/model.hpp"
#include "tensormass/parallel/mesh_cut.hpp"

namespace tensormass {

class Distribution {
 public:
  /// The model holds the whole mesh. cell_owner: the rank of every cell
  /// (cell_count, values in [0, size)). Throws std::invalid_argument on a
  /// wrong size or rank.
  Distribution(const Model& model, std::vector<int> cell_owner, int rank, int size);
  /// The model holds this rank's part of the mesh, cut as `cut` says
  /// (parallel::cut_mesh). Throws std::invalid_argument when the cut does not fit the model.
  Distribution(const Model& model, CellCut cut, int rank, int size);

  int rank() const { return rank_; }
  int size() const { return size_; }
  /// Whether the model holds only this rank's part of the mesh.
  bool holds_part() const { return holds_part_; }
  /// A cell's index in the whole mesh, and the whole mesh's cell count.
  int global_cell(int cell) const { return cut_.global_cell[cell]; }
  int whole_cell_count() const { return cut_.whole_cell_count; }
  /// The model's cell of the whole mesh's cell `global`, or -1 when this rank does not hold it.
  int local_cell(int global) const;
  /// Cells of this rank's part: its energy terms and output piece.
  bool owns_cell(int cell) const { return cut_.cell_owner[cell] == rank_; }
  int cell_owner(int cell) const { return cut_.cell_owner[cell]; }
  /// Cells whose kernels this rank runs: its own and those touching its nodes.
  bool assembles_cell(int cell) const { return assembled_[cell] != 0; }
  int assembled_cell_count() const { return assembled_count_; }
  /// A node belongs to the lowest rank among its cells' owners (rank 0 for a node in no cell).
  bool owns_node(int node) const { return cut_.node_owner[node] == rank_; }
  int node_owner(int node) const { return cut_.node_owner[node]; }

  /// free_dof_count: each free dof's row in the rank-by-rank numbering.
  const std::vector<int>& global_row() const { return global_row_; }
  /// This rank's free dofs (free indices, ascending): global rows
  /// first_global_row() .. first_global_row() + size - 1, in this order.
  const std::vector<int>& owned_free_rows() const { return owned_free_rows_; }
  int first_global_row() const { return first_global_row_; }

  /// Zeroes the entries of other ranks' dofs: v is dof_count (keep_own_dofs)
  /// or free_dof_count (keep_own_free) long, else std::invalid_argument.
  void keep_own_dofs(std::span<double> v) const;
  void keep_own_free(std::span<double> v) const;
  /// keep_own_* then the sum over ranks: every rank gets the complete vector.
  void complete_dofs(std::span<double> v) const;
  void complete_free(std::span<double> v) const;
  /// values: one per cell of the model. Every cell gets its owner's value
  /// (collective: every rank calls it; the same bits on every rank).
  void share_cell_values(std::span<double> values) const;

 private:
  void build();

  const Model* model_;
  int rank_, size_;
  bool holds_part_ = false;
  CellCut cut_;
  std::vector<char> assembled_;
  int assembled_count_ = 0;
  std::vector<int> global_row_, owned_free_rows_;
  std::vector<int> foreign_nodes_, foreign_free_rows_;  ///< other ranks' nodes and free rows
  int first_global_row_ = 0;
};

}  // namespace tensormass

#endif
