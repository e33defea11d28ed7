/// \file distribution.hpp
/// How a model's work is shared among MPI ranks. A rank's model holds
/// either the whole mesh (replicated) or its part of it (MeshPart: the
/// cells it assembles and their nodes, numbered in the part). Each rank
/// owns the cells of its part of the cut and the nodes whose lowest-ranked
/// cell is its own. A rank assembles every cell that touches one of its
/// nodes, so its rows (its nodes' dofs) of the forces and of the tangent
/// are complete with no communication; other rows are partial and are
/// never read.
///
/// With the whole mesh every rank holds the whole state: complete_* keep a
/// rank's own rows and sum over ranks. With a part the state is divided
/// (divides_state()): its vectors run over the part's nodes, a rank
/// computes its own rows only and receives its ghost nodes' values (the
/// other nodes of its part) from their owners (share_ghost_*); whole_* and
/// local_* move a state between the part and the whole mesh. The linear
/// solver numbers the free dofs rank by rank (global_row) so that each
/// rank's rows are one contiguous range.
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
  /// A node's index in the whole mesh, and the whole mesh's node count.
  int global_node(int node) const { return holds_part_ ? cut_.global_node[node] : node; }
  int whole_node_count() const { return holds_part_ ? cut_.whole_node_count : model_->mesh().node_count(); }
  /// Per node of the part, its index in the whole mesh (empty for the whole mesh).
  const std::vector<int>& global_nodes() const { return cut_.global_node; }
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
  /// With a part, only after number_global_rows().
  const std::vector<int>& global_row() const { return global_row_; }
  /// A free dof's index among the whole mesh's free dofs (serial order);
  /// with a part, only after number_global_rows().
  int whole_free_row(int row) const { return holds_part_ ? whole_free_row_[row] : row; }
  /// The free dofs of the whole mesh: the rank-by-rank numbering's size.
  int global_row_count() const { return global_row_count_; }
  /// With a part: numbers the free dofs rank by rank and in the whole
  /// mesh's order (whole_free, local_free). Collective; a no-op with the whole mesh.
  void number_global_rows();
  /// This rank's free dofs (free indices, ascending): global rows
  /// first_global_row() .. first_global_row() + size - 1, in this order.
  const std::vector<int>& owned_free_rows() const { return owned_free_rows_; }
  int first_global_row() const { return first_global_row_; }

  /// Zeroes the entries of other ranks' dofs: v is dof_count (keep_own_dofs)
  /// or free_dof_count (keep_own_free) long, else std::invalid_argument.
  void keep_own_dofs(std::span<double> v) const;
  void keep_own_free(std::span<double> v) const;
  /// keep_own_* then the sum over ranks: every rank gets the complete vector
  /// (with a part: keep_own_* then share_ghost_*, the part's entries complete).
  void complete_dofs(std::span<double> v) const;
  void complete_free(std::span<double> v) const;
  /// values: one per cell of the model. Every cell gets its owner's value
  /// (collective: every rank calls it; the same bits on every rank). With a
  /// part: one message per neighbour, else a sum over the ranks of one
  /// value per cell of the whole mesh.
  void share_cell_values(std::span<double> values) const;

  /// Whether each rank computes only its own rows of the state (its model
  /// holds a part of the mesh): see the file's comment.
  bool divides_state() const { return holds_part_; }
  /// This rank's nodes, ascending.
  const std::vector<int>& own_nodes() const { return own_nodes_; }
  /// The nodes of this part's cells that other ranks own, ascending (empty
  /// unless divides_state()).
  const std::vector<int>& ghost_nodes() const { return ghost_nodes_; }
  /// The ranks this one exchanges ghost values with, ascending, and the
  /// nodes it sends to and receives from neighbours()[i] (ascending).
  const std::vector<int>& neighbours() const { return neighbours_; }
  const std::vector<int>& sent_nodes(int i) const { return links_[i].send_nodes; }
  const std::vector<int>& received_nodes(int i) const { return links_[i].receive_nodes; }
  /// The cells this rank owns that neighbours()[i] holds, and the cells it
  /// holds that neighbours()[i] owns (ascending).
  const std::vector<int>& sent_cells(int i) const { return links_[i].send_cells; }
  const std::vector<int>& received_cells(int i) const { return links_[i].receive_cells; }
  /// Sets the ghost nodes' entries of `a` (and of `b`, when not empty; both
  /// dof_count long) to their owners' values, in one message per
  /// neighbour. Collective over the neighbours; a no-op unless divides_state().
  void share_ghost_dofs(std::span<double> a, std::span<double> b = {}) const;
  /// The same for a vector over the free dofs (free_dof_count long).
  void share_ghost_free(std::span<double> v) const;
  /// Zeroes the ghost nodes' entries of `v` (dof_count long).
  void zero_ghost_dofs(std::span<double> v) const;

  /// A divided vector over the part's dofs (dof_count) or free dofs
  /// (free_dof_count) made whole: the whole mesh's dofs, or its free dofs in
  /// their serial order, each from its owner, the same bits on every rank.
  /// Collective (a sum over the ranks of a whole-length vector: for
  /// checkpoints, tracks and the report). With the whole mesh: complete_*.
  std::vector<double> whole_dofs(std::span<const double> v) const;
  std::vector<double> whole_free(std::span<const double> v) const;
  /// The part's entries of a whole vector (the inverse of whole_*).
  std::vector<double> local_dofs(std::span<const double> whole) const;
  std::vector<double> local_free(std::span<const double> whole) const;

 private:
  void build();
  void build_ghost_links();
  void number_whole_mesh_rows();

  /// What this rank sends to and receives from one neighbour.
  struct GhostLink {
    int rank = 0;
    std::vector<int> send_nodes, receive_nodes;
    std::vector<int> send_dofs, receive_dofs;  ///< dofs of those nodes
    std::vector<int> send_free, receive_free;  ///< their free rows
    std::vector<int> send_cells, receive_cells;
  };
  /// What a vector exchanged with the neighbours runs over.
  enum class Entries { dofs, free, cells };
  static const std::vector<int>& sent(const GhostLink& link, Entries entries);
  static const std::vector<int>& received(const GhostLink& link, Entries entries);
  /// Sends values[sent] to each neighbour and writes what comes back at received.
  void exchange(std::span<double> a, std::span<double> b, Entries entries) const;

  const Model* model_;
  int rank_, size_;
  bool holds_part_ = false;
  CellCut cut_;
  std::vector<char> assembled_;
  int assembled_count_ = 0;
  std::vector<int> global_row_, owned_free_rows_;
  std::vector<int> foreign_nodes_, foreign_free_rows_;  ///< other ranks' nodes and free rows
  int first_global_row_ = 0, global_row_count_ = 0;
  std::vector<int> whole_free_row_;  ///< with a part: each free dof's index among the whole mesh's free dofs
  std::vector<int> own_nodes_, ghost_nodes_, neighbours_;
  std::vector<GhostLink> links_;
  mutable std::vector<std::vector<double>> send_buffers_, receive_buffers_;
};

}  // namespace tensormass

#endif
