/// \file criteria_screen.hpp
/// Which cells' criteria must be evaluated again, so that an evaluation
/// costs in proportion to the cells that move rather than to the mesh.
///
/// For criteria that are functions of the displacement gradients H_q at the
/// quadrature points (R_NL, R_E: Criterion::screenable), a cell's value moves
/// by at most a delta + delta^2 / 2 when every |H'_q - H_q|_F <= delta, with
/// a from the value itself (Criterion::gradient_norm_bound, change_slope);
/// and delta <= G max_j |u'_j - u_j| over the cell's nodes j, with
/// G = max_q sum_j |grad N_j(x_q)| (rest gradients, from the constants).
/// From the values of its last evaluation each cell gets a slack: how far
/// (in metres) its nodes may move before one of its values could reach a
/// decision boundary (a threshold, or threshold x hysteresis with
/// downgrade). A cell whose nodes stayed within it keeps its values: they
/// are on the same side of every boundary as fresh ones, so every decision
/// is the one a full evaluation takes.
///
/// The nodes' motion is measured between successive evaluations, and
/// summed per chunk of 64 consecutive cells: each evaluation adds to a
/// chunk's running motion the largest distance one of its nodes moved since
/// the previous one, less what all its nodes moved alike (sum_j grad N_j = 0,
/// so a common motion w leaves H unchanged and delta H = sum_j (du_j - w) x
/// grad N_j); the triangle inequality adds the evaluations up. A cell
/// keeps its values while its chunk's running motion stays below the
/// cell's expiry (the running motion when it was evaluated, plus its
/// slack). A chunk whose cells all expire later is skipped whole, so a
/// quiet region costs a few node reads per evaluation, not a pass over its
/// cells. Round-off in H (about N eps |u| G) is covered by a margin of
/// 1e-13 |u| per evaluation, and the values' own by a relative margin of
/// 1e-12 on each boundary.
#ifndef TENSORMASS_ADAPTIVITY_CRITERIA_SCREEN_HPP
#define TENSORMASS_ADAPTIVITY_CRITERIA_SCREEN_HPP

#include <span>
#include <vector>

#include "tensormass/adaptivity/criteria.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {

/// Per cell flags of CriteriaScreen::select.
enum ScreenFlag : unsigned char {
  kScreenKeep = 0,      ///< within its slack, or cannot move: keeps its values
  kScreenEvaluate = 1,  ///< evaluate (then CriteriaScreen::settle)
};

/// G = max_q sum_j |grad N_j(x_q)| of a cell (rest shape gradients, read
/// from its constants: kernel_abi.h), so that every |delta H_q|_F <= G
/// max_j |delta u_j|.
double shape_gradient_sum(const Model& model, int cell);

class CriteriaScreen {
 public:
  /// Cells per chunk: consecutive cells share their nodes' motion.
  static constexpr int kChunkCells = 64;

  /// criteria: every one screenable(), thresholds one per criterion;
  /// hysteresis: the calm boundary's factor (threshold x hysteresis) when
  /// downgrade is on, 0 without. The model must outlive the screen.
  /// std::invalid_argument on a criterion that is not screenable.
  CriteriaScreen(const Model& model, std::vector<const Criterion*> criteria, std::vector<double> thresholds,
                 double hysteresis);

  /// True when every criterion is screenable().
  static bool applies(std::span<const Criterion* const> criteria);

  /// Forgets every slack: the next select() flags every movable cell.
  void reset();
  /// Forgets one cell's slack (it became movable): the next select() flags it.
  void forget(int cell);

  /// Measures the nodes' motion since the previous select() (u: dof_count;
  /// u becomes the next one's reference) and flags every cell (flags:
  /// cell_count): kScreenEvaluate when movable[cell] is not 0 and its
  /// nodes may have moved past its slack, else kScreenKeep. Called by every
  /// thread of an enclosing parallel region (or serially); returns after a
  /// barrier.
  void select(std::span<const double> u, std::span<const unsigned char> movable, std::span<unsigned char> flags);

  /// After a kScreenEvaluate cell's values (values[criterion][cell]) were
  /// computed at select()'s u: its new slack. Thread-safe across cells.
  void settle(int cell, const std::vector<std::vector<double>>& values);

  /// The displacement of the last select() (dof_count).
  const std::vector<double>& last_displacement() const { return reference_; }
  /// Cells flagged kScreenEvaluate, summed over the select() calls, and the number of calls.
  long evaluated_cells() const { return evaluated_; }
  long evaluations() const { return evaluations_; }

 private:
  void build_chunks();
  void measure_nodes(std::span<const double> u);
  /// The largest |du_j - w| + 1e-13 |u_j| over the chunk's nodes, w the middle of their motions du.
  double chunk_motion(int chunk) const;
  /// Flags one chunk's cells; returns how many are flagged kScreenEvaluate.
  int flag_chunk(int chunk, std::span<const unsigned char> movable, std::span<unsigned char> flags);
  /// Largest |delta H| the cell's values allow before one may reach a boundary.
  double gradient_change_allowed(int cell, const std::vector<std::vector<double>>& values) const;

  const Model* model_;
  std::vector<const Criterion*> criteria_;
  std::vector<double> thresholds_;
  double hysteresis_;
  /// What settle() and select() read of a cell, side by side (one cache line).
  struct CellSlack {
    double expiry;                ///< its values hold while its chunk's running motion is below this
    double inverse_gradient_sum;  ///< 1 / G, G = max_q sum_j |grad N_j(x_q)|
  };
  std::vector<CellSlack> cells_;
  std::vector<int> chunk_first_;  ///< chunks + 1: each chunk's first cell (its cells are consecutive)
  std::vector<int> chunk_node_offsets_, chunk_nodes_;  ///< each chunk's distinct nodes
  std::vector<double> chunk_motion_;                   ///< per chunk: the running sum of its largest node motions
  std::vector<double> chunk_expiry_;  ///< per chunk: the earliest expiry of its movable cells (-inf: unknown)
  std::vector<double> reference_;     ///< dof_count: the displacement of the last select
  std::vector<double> delta_;         ///< dof_count: u - reference at the last select
  std::vector<double> length_;        ///< per node: |u| at the last select
  long evaluated_ = 0, evaluations_ = 0;
};

}  // namespace tensormass

#endif
