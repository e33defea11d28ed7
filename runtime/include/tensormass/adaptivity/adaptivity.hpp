/// \file adaptivity.hpp
/// The adaptive model: every `every` steps each element's criteria are
/// evaluated; an element that fails any enabled criterion climbs one rung
/// of the law ladder (default hooke -> stvk) by swapping its kernel (O(1)),
/// optionally blended over `blend_steps` steps; with downgrade on, an
/// upgraded element whose criteria all stay within threshold x hysteresis
/// for `calm_steps` evaluations descends one rung, and back on its initial
/// law it has its initial kernel exactly.
#ifndef TENSORMASS_ADAPTIVITY_HPP
#define TENSORMASS_ADAPTIVITY_HPP

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tensormass/adaptivity/adaptivity_settings.hpp"
#include "tensormass/adaptivity/criteria.hpp"
#include "tensormass/adaptivity/criteria_screen.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/io/field.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {

/// Counts after one evaluation.
struct AdaptivityRecord {
  int step = 0;
  int upgrades = 0;
  int downgrades = 0;
  std::vector<std::pair<std::string, int>> cells_per_law;
};

/// A run's evaluations in bounded memory (a run streams every one to a
/// file, simulation/): the first kListed in full, the first kListed of
/// those that switched cells, and counts of all.
struct AdaptivityRecords {
  static constexpr std::size_t kListed = 1000;
  std::vector<AdaptivityRecord> listed;
  std::vector<AdaptivityRecord> switching;  ///< the first evaluations that switched cells
  long evaluations = 0;
  long switching_evaluations = 0;
  void add(const AdaptivityRecord& record) {
    ++evaluations;
    if (listed.size() < kListed) listed.push_back(record);
    if (record.upgrades + record.downgrades == 0) return;
    ++switching_evaluations;
    if (switching.size() < kListed) switching.push_back(record);
  }
};

/// What the adaptive model carries from one evaluation to the next besides
/// the model's laws and blends, for checkpoints.
struct AdaptivityMemory {
  std::vector<int> calm_evaluations;        ///< per cell
  std::vector<std::vector<double>> values;  ///< per criterion, per cell: the last evaluation
  int total_switches = 0;
  double criteria_seconds = 0;
  std::vector<double> criterion_seconds;
  AdaptivityRecords records;
  AdaptivityRecord last_record;
};

class Adaptivity {
 public:
  /// The settings must name known criteria and a ladder of at least two
  /// laws with kernels for the mesh's elements (validated by scene/);
  /// std::invalid_argument otherwise. The assembler gives R_S its nodal forces.
  Adaptivity(const AdaptivitySettings& settings, Model& model, const Assembler& assembler);

  /// The evaluation before the first step, at displacement u (dof_count):
  /// cells climb as many rungs as the criteria ask (a threshold of 0 puts
  /// every cell on the last rung from the start). Recorded as step 0 when
  /// it switched cells. Returns the number of switches.
  int start(std::span<const double> u);
  /// Moves every blending cell one step towards its new law (call once per
  /// time step, before the next solve).
  void advance_blends();
  /// Evaluates the criteria at displacement u (dof_count) when `step` is a
  /// multiple of `every`, switches laws, and returns the number of switches.
  int update(std::span<const double> u, int step);

  /// Cell data for output: one array per criterion (its values at the last
  /// evaluation; cells the screen skipped are evaluated here first), and
  /// `state`: the largest criterion / threshold in [0, 1] for a cell under
  /// its initial law (1 = at the threshold), 2 once switched.
  std::vector<io::Field> cell_fields() const;

  int total_switches() const { return total_switches_; }
  double criteria_seconds() const { return criteria_seconds_; }
  /// Running time of each criterion (same order as criterion_names()).
  const std::vector<double>& criterion_seconds() const { return criterion_seconds_; }
  const AdaptivityRecords& records() const { return records_; }
  /// The latest evaluation's record (records().evaluations counts them).
  const AdaptivityRecord& last_record() const { return last_record_; }
  /// The criteria screen (criteria_screen.hpp), or null when every cell is evaluated every time.
  const CriteriaScreen* screen() const { return screen_.get(); }
  const std::vector<std::string>& criterion_names() const { return names_; }
  /// The last evaluation of criterion `index` (criterion_names() order), per cell.
  const std::vector<double>& criterion_values(int index) const {
    refresh_values();
    return values_.at(index);
  }
  AdaptivityMemory memory() const;
  /// Takes a saved memory back (its sizes must fit: std::invalid_argument otherwise).
  void restore(AdaptivityMemory memory);
  /// Follows a mesh change (refinement): from now on works on
  /// `model` and `assembler` (built on the new mesh, their laws already
  /// carried over), cell c taking the per-cell state (last criteria values,
  /// calm count, initial rung) of old cell origin[c]. The run-level counts
  /// (switches, criteria seconds, records) are kept. std::invalid_argument
  /// when a ladder law has no kernel for an element type of the new mesh,
  /// or when origin does not have one entry per new cell, each an old cell.
  void follow(Model& model, const Assembler& assembler, std::span<const int> origin);
  /// Over MPI ranks: each rank evaluates and decides its own cells, then
  /// every rank applies every rank's moves (one sum over the ranks per
  /// evaluation, which also shares the calm counts), so the laws stay the
  /// same everywhere; nullptr: one process. The distribution must outlive
  /// this object (or be replaced by another call).
  void distribute(const Distribution* distribution);
  /// Over MPI ranks each rank holds the criteria values of its own cells
  /// only (all its output piece needs); this gives every rank all of them
  /// (for a checkpoint, or before a new cut). Collective: every rank calls it.
  void share_values();

 private:
  /// Evaluates the criteria at u, decides and switches every cell; adds
  /// the switches and the laws' counts to the record.
  void assess(std::span<const double> u, AdaptivityRecord& record);
  void refresh_rungs();
  /// Lists rungs_ for the kernels of the model's element types.
  void find_rungs();
  /// Builds screen_ for the model when the settings and criteria allow.
  void make_screen();
  /// Whether a cell's decision can ever move it (its rung, the ladder, downgrade, ownership).
  bool can_move(int cell, int rung) const;
  /// Every slack forgotten: the next screened evaluation evaluates every movable cell.
  void restart_screen();
  /// The screen for this evaluation, or null while it is paused (busy scenes).
  CriteriaScreen* screen_now();
  /// After a screened evaluation of `evaluated` cells: pauses the screen when it saved little.
  void judge_screen(long evaluated);
  /// movable_[cell] = state; the screen forgets a cell that starts to move.
  void set_movable(int cell, unsigned char state);
  /// The values of the cells the screen kept, computed at the last
  /// evaluation's displacement (the values are then what a full evaluation
  /// gives). Logically const: the values are computed lazily.
  void refresh_values() const;
  /// Every criterion on the block's cells (flags: CriteriaScreen's, or null for every cell).
  void evaluate_criteria(const ElementBlock& block, std::span<const double> u, const unsigned char* flags,
                         std::vector<double>& seconds) const;
  signed char decide(int cell, int rung);
  void record_laws(AdaptivityRecord& record) const;
  void record_cells_per_law(AdaptivityRecord& record) const;
  /// Whether this rank counts the cell in the records: its owner does (every cell on one process).
  bool counts(int cell) const;
  /// Applies moves_ (in cell order) and counts them in the record.
  void switch_moved_cells(AdaptivityRecord& record);
  /// moves_[cell] for one cell after its values were evaluated or kept
  /// (flags: the screen's, or null); returns 1 when it moves.
  int decide_cell(int cell, const unsigned char* flags);
  /// movable_ per cell: it cannot move (or is another rank's); it must be
  /// decided; or its last decision was to stay, on the values and rung it
  /// still has, with no downgrade (deciding again gives the same).
  enum Movable : unsigned char { kStill = 0, kMustDecide = 1, kQuiet = 2 };
  /// Index of the kernel's law on the ladder, or -1.
  int rung_of(const tm_kernel& kernel) const;
  /// A criterion whose rung is above `rung` fails on the cell.
  bool fails_above(int cell, int rung) const;
  /// Every criterion whose rung is at or above `rung` is calm on the cell.
  bool calm_at(int cell, int rung) const;
  void switch_law(int cell, const std::string& law);

  AdaptivitySettings settings_;
  Model* model_;
  const Assembler* assembler_;
  const Distribution* distribution_ = nullptr;
  /// Sums each cell's move and calm count over the ranks (each cell decided by its owner only).
  void share_decisions();
  std::vector<double> nodal_forces_;  ///< dof_count, for R_S
  std::vector<std::unique_ptr<Criterion>> criteria_;
  std::vector<double> thresholds_;
  std::vector<int> target_rungs_;  ///< per criterion: the ladder index it asks for
  std::vector<std::string> names_;
  std::vector<char> quality_;                        ///< per criterion: Criterion::is_quality
  mutable std::vector<std::vector<double>> values_;  ///< per criterion, per cell
  std::unique_ptr<CriteriaScreen> screen_;           ///< null: every cell evaluated every time
  std::vector<unsigned char> movable_;               ///< per cell: Movable, kept with cell_rungs_
  std::vector<int> cells_per_rung_;                  ///< kept with cell_rungs_
  int off_ladder_cells_ = 0;
  std::vector<unsigned char> screen_flags_;  ///< per cell: CriteriaScreen::select's flags
  mutable bool stale_ = false;               ///< kept cells' values are from earlier evaluations
  bool screen_warming_ = true;               ///< the screen's next evaluation starts every slack
  int screen_pause_ = 0;                     ///< evaluations left without the screen
  int top_target_ = 0;                       ///< highest rung a criterion asks for
  std::vector<int> calm_evaluations_;        ///< per cell
  std::vector<std::pair<const tm_kernel*, int>>
      rungs_;                       ///< every kernel of a ladder law on the mesh's elements -> rung
  std::vector<signed char> moves_;  ///< per cell, scratch of assess: -1, 0, +1
  std::vector<signed char> initial_rungs_, cell_rungs_;  ///< per cell: rung_of the initial and current kernel
  long rungs_revision_ = -1;                             ///< the model's law_revision when cell_rungs_ was right
  bool needs_force_ = false;
  int total_switches_ = 0;
  mutable double criteria_seconds_ = 0;
  std::vector<double> criterion_seconds_;
  AdaptivityRecords records_;
  AdaptivityRecord last_record_;
};

}  // namespace tensormass

#endif
