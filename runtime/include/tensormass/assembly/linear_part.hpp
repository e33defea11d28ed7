/// \file linear_part.hpp
/// The constant part of the internal forces. Every cell whose kernel is
/// linear (tm_kernel::linear: Hooke) and not blending contributes g_e = K_e u_e
/// with a constant K_e, so all of them are folded once into one symmetric
/// matrix K_L over all dofs, stored as d by d node blocks on the NodeGraph:
/// their forces are one block product K_L u and their tangent a copy, and
/// per step only the other cells run kernels.
///
/// When cells change law, update() subtracts the K_e of the cells that
/// left the linear set and adds those that joined, in cell order: the cost
/// is proportional to the change and the result is deterministic. Sums
/// therefore differ from a fresh per-cell assembly by round-off only. (When
/// a switch recomputed a cell's constants, Model::consts_revision, the whole
/// part is folded afresh.) The blocks of a node that no folded cell holds
/// any more are set to exact zeros, and the product skips those nodes' rows
/// when they are many: its cost follows the folded region.
#ifndef TENSORMASS_ASSEMBLY_LINEAR_PART_HPP
#define TENSORMASS_ASSEMBLY_LINEAR_PART_HPP

#include <span>
#include <vector>

#include "tensormass/assembly/node_graph.hpp"
#include "tensormass/assembly/sparse_matrix.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {

class LinearPart {
 public:
  /// An empty linear part (nothing folded) for `model`; `free_pattern` is
  /// the pattern of the tangent over the free dofs (Assembler::pattern()),
  /// kept by reference like `graph`.
  LinearPart(const Model& model, const NodeGraph& graph, const SparseMatrix& free_pattern);

  /// Folds the cells that are linear now and unfolds those that are not,
  /// when the model's laws changed since the last call (Model::law_revision).
  /// Returns the number of cells folded or unfolded.
  int update();
  bool folded(int cell) const { return folded_kernel_[cell] != nullptr; }
  int folded_count() const { return folded_count_; }
  /// Cells folded or unfolded by update() since construction (the first
  /// update folds every linear cell).
  long changes() const { return changes_; }

  /// What the folded matrix is made of, for a checkpoint: its sums depend
  /// on the order of the law switches (see above), so a resumed run takes
  /// them back rather than folding afresh.
  struct Saved {
    std::vector<double> blocks;
    std::vector<const tm_kernel*> folded;  ///< per cell
    int folded_count = 0;
    long changes = 0;
    bool constants_changed = false;  ///< a cell's constants were recomputed since the last update()
  };
  Saved saved() const;
  /// Takes `saved` back; the next update() brings it up to the model's laws
  /// as the interrupted run's next update() would have.
  void restore(Saved saved);

  /// g (dof_count) = K_L u (dof_count).
  void multiply(std::span<const double> u, std::span<double> g) const;
  /// values (free_pattern's non-zeros) = K_L restricted to the free dofs.
  /// The free pattern must be built by then; the first call after a fold
  /// or pattern_changed() maps it.
  void copy_free(std::span<double> values) const;
  /// The free pattern given at construction was rebuilt or dropped (Assembler::distribute).
  void pattern_changed();

 private:
  void add_cell(int cell, const tm_kernel& kernel, double sign);
  /// node_folds_ and active_nodes_ from folded_kernel_.
  void count_node_folds();
  /// A cell folded (change 1) or unfolded (-1): its nodes' counts.
  void count_cell_fold(int cell, int change);
  /// Zeroes the blocks of a node no folded cell touches (row and column).
  void unfold_node(int node);
  void list_active_nodes();
  /// Sizes blocks_ at the first fold: a run with no linear cell holds
  /// none (at a million tets about 200 MB).
  void allocate();
  /// free_to_block_ for the free pattern as it is now, at the first
  /// copy_free(): a run that never asks for a tangent (explicit) holds none.
  void map_free_pattern() const;

  const Model* model_;
  const NodeGraph* graph_;
  const SparseMatrix* free_pattern_;
  int dim_;
  std::vector<double> blocks_;              ///< graph columns by d by d, row-major blocks; empty until a cell folds
  mutable std::vector<int> free_to_block_;  ///< free_pattern non-zero -> index in blocks_
  mutable bool mapped_ = false;             ///< free_to_block_ matches the free pattern
  std::vector<const tm_kernel*> folded_kernel_;  ///< per cell: the kernel folded, or nullptr
  int folded_count_ = 0;
  std::vector<int> node_folds_;    ///< per node: the folded cells that hold it
  std::vector<int> active_nodes_;  ///< the nodes with node_folds_ > 0, in order
  long changes_ = 0;
  long seen_revision_ = -1;
  long seen_consts_revision_ = 0;
};

}  // namespace tensormass

#endif
