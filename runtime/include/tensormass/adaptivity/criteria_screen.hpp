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
/// The nodes' motion is measured between successive evaluations: each
/// evaluation takes from every kept cell's slack the largest distance one of
/// its nodes moved since the previous evaluation (the triangle inequality
/// adds them up), and an evaluated cell's slack starts again from its new
/// values. Round-off in H (about N eps |u| G) is covered by a margin of
/// 1e-13 |u| per evaluation, and the values' own by a relative margin of
/// 1e-12 on each boundary.
#ifndef TENSORMASS_ADAPTIVITY_CRITERIA_SCREEN_HPP
#define TENSORMASS_ADAPTIVITY_CRITERIA_SCREEN_HPP

#include <span>
#include <vector>

#include "tensormass/adaptivity/criteria.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {

/// Per cell flags of CriteriaScreen::flag_block.
enum ScreenFlag : unsigned char {
  kScreenKeep = 0,      ///< within its slack: keeps its values
  kScreenEvaluate = 1,  ///< evaluate (then CriteriaScreen::settle)
  kScreenIdle = 2,      ///< cannot move (or another rank's): not evaluated, slack forgotten
};

class CriteriaScreen {
 public:
  /// criteria: every one screenable(), thresholds one per criterion;
  /// hysteresis: the calm boundary's factor (threshold x hysteresis) when
  /// downgrade is on, 0 without. The model must outlive the screen.
  /// std::invalid_argument on a criterion that is not screenable.
  CriteriaScreen(const Model& model, std::vector<const Criterion*> criteria, std::vector<double> thresholds,
                 double hysteresis);

  /// True when every criterion is screenable().
  static bool applies(std::span<const Criterion* const> criteria);

  /// Forgets every slack: the next evaluation evaluates every movable cell.
  void reset();

  /// The nodes' motion since the previous measure() (u: dof_count), and u
  /// becomes the next one's reference. Called by every thread of an
  /// enclosing parallel region (or serially); returns after a barrier.
  void measure(std::span<const double> u);
  /// After measure(), flags the block's cells (flags: cell_count):
  /// kScreenIdle where movable[cell] is 0, else kScreenKeep when its nodes
  /// stayed within its slack, else kScreenEvaluate. Shares the cells among
  /// the threads like Criterion::evaluate_block (static schedule over
  /// block.count(), no barrier), so a thread evaluates the cells it flagged.
  void flag_block(const ElementBlock& block, std::span<const unsigned char> movable, std::span<unsigned char> flags);
  /// Counts an evaluation (for evaluated_cells() / evaluations()).
  void count_evaluation() { ++evaluations_; }

  /// After a kScreenEvaluate cell's values (values[criterion][cell]) were
  /// computed at measure()'s u: its new slack. Thread-safe across cells.
  void settle(int cell, const std::vector<std::vector<double>>& values);

  /// The slack of a cell in metres (<= 0: evaluated at the next evaluation).
  double slack(int cell) const { return slack_[cell]; }
  /// The displacement of the last measure() (dof_count).
  const std::vector<double>& last_displacement() const { return reference_; }
  /// Cells flagged kScreenEvaluate, summed over the evaluations, and the number of evaluations.
  long evaluated_cells() const { return evaluated_; }
  long evaluations() const { return evaluations_; }

 private:
  /// Largest |delta H| the cell's values allow before one may reach a boundary.
  double gradient_change_allowed(int cell, const std::vector<std::vector<double>>& values) const;

  const Model* model_;
  std::vector<const Criterion*> criteria_;
  std::vector<double> thresholds_;
  double hysteresis_;
  std::vector<double> gradient_sum_;  ///< per cell: G = max_q sum_j |grad N_j(x_q)|
  std::vector<double> slack_;         ///< per cell, metres
  std::vector<double> reference_;     ///< dof_count: the displacement of the last measure
  std::vector<double> motion_;        ///< per node: |u - reference| + 1e-13 |u| at the last measure
  std::vector<double> length_;        ///< per node: |u| at the last measure
  long evaluated_ = 0, evaluations_ = 0;
};

}  // namespace tensormass

#endif
