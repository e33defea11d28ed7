#include "tensormass/adaptivity/adaptivity.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string_view>
#include <type_traits>

#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/parallel/mpi_world.hpp"

namespace tensormass {

namespace {
constexpr int kParallelCells = 4096;  // below this a parallel region costs more than it saves
/// Settling a cell's slack costs more than evaluating it: when the screen
/// leaves more than this share of the cells to evaluate, the next
/// kScreenPause evaluations evaluate every cell and skip the screen.
constexpr double kScreenBusyShare = 0.25;
constexpr int kScreenPause = 8;

/// A cell keeps its split over a switch (fbar, anp): each rung must have a
/// kernel of it for every such cell of a material on the ladder.
void check_split_kernels(const std::vector<std::string>& ladder, const Model& model,
                         const std::vector<bool>& on_ladder) {
  std::set<const tm_kernel*> checked;
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const tm_kernel& kernel = model.kernel(cell);
    if (!on_ladder[model.material(cell)] || !locking_free_split(kernel) || !checked.insert(&kernel).second) continue;
    for (const std::string& law : ladder)
      if (!model.law_kernel(cell, law))
        throw InputError(model.material_laws(model.material(cell)).owner() + ": its " + kernel.element +
                         " cells use split " + kernel.split + ", for which the adaptivity ladder's law '" + law +
                         "' has no kernel (anp needs a law with a bulk part U(J): not stvk or corotational; "
                         "docs/formulations.md); take a ladder such as [hooke, neohookean]");
  }
}

/// Every ladder law must have a kernel for every element type of the mesh,
/// and compute the same leading constants from each material that starts on
/// the ladder: its cells switch laws keeping their constants, and the
/// criteria evaluate the ladder's laws on them.
void check_ladder(const std::vector<std::string>& ladder, const Model& model) {
  if (ladder.size() < 2) throw std::invalid_argument("an adaptivity ladder needs at least two laws");
  for (const std::string& law : ladder)
    for (const ElementBlock& block : model.mesh().blocks)
      if (!Registry::instance().find(law, block.element->name, "whole"))
        throw std::invalid_argument("adaptivity ladder: no kernel for law '" + law + "' on " + block.element->name);
  std::vector<bool> on_ladder(model.material_count(), false);
  for (int cell = 0; cell < model.cell_count(); ++cell)
    if (std::find(ladder.begin(), ladder.end(), model.kernel(cell).law) != ladder.end())
      on_ladder[model.material(cell)] = true;
  for (int m = 0; m < model.material_count(); ++m)
    for (std::size_t r = 1; on_ladder[m] && r < ladder.size(); ++r)
      if (!model.material_laws(m).share_constants(ladder[0], ladder[r]))
        throw InputError(model.material_laws(m).owner() + ": the ladder's laws " + ladder[0] + " and " + ladder[r] +
                         " do not compute the same constants from this material (a ladder takes laws with the "
                         "same parameters and derived constants, such as hooke, stvk and neohookean)");
  check_split_kernels(ladder, model, on_ladder);
}

/// The ladder index a criterion asks for: its rung, or the last law.
int target_rung(const CriterionSpec& criterion, const std::vector<std::string>& ladder) {
  if (criterion.rung.empty()) return static_cast<int>(ladder.size()) - 1;
  const auto found = std::find(ladder.begin(), ladder.end(), criterion.rung);
  if (found == ladder.end() || found == ladder.begin())
    throw std::invalid_argument("criterion " + criterion.name + ": rung '" + criterion.rung +
                                "' is not a law above the first on the ladder");
  return static_cast<int>(found - ladder.begin());
}
}  // namespace

Adaptivity::Adaptivity(const AdaptivitySettings& settings, Model& model, const Assembler& assembler)
    : settings_(settings), model_(&model), assembler_(&assembler) {
  check_ladder(settings.ladder, model);
  for (const CriterionSpec& criterion : settings.criteria) {
    const int target = target_rung(criterion, settings.ladder);
    criteria_.push_back(make_criterion(criterion.name, {settings.ladder.front(), settings.ladder[target]}));
    thresholds_.push_back(criterion.threshold);
    target_rungs_.push_back(target);
    names_.push_back(criterion.name);
    quality_.push_back(criteria_.back()->is_quality());
    needs_force_ = needs_force_ || criteria_.back()->needs_force();
  }
  find_rungs();
  values_.assign(criteria_.size(), std::vector<double>(model.cell_count(), 0.0));
  initial_rungs_.resize(model.cell_count());
  for (int cell = 0; cell < model.cell_count(); ++cell)
    initial_rungs_[cell] = static_cast<signed char>(rung_of(model.initial_kernel(cell)));
  criterion_seconds_.assign(criteria_.size(), 0.0);
  calm_evaluations_.assign(model.cell_count(), 0);
  for (int target : target_rungs_) top_target_ = std::max(top_target_, target);
  make_screen();
}

void Adaptivity::make_screen() {
  std::vector<const Criterion*> criteria;
  for (const auto& criterion : criteria_) criteria.push_back(criterion.get());
  screen_.reset();
  stale_ = false;
  if (!settings_.screen || !CriteriaScreen::applies(criteria)) return;
  screen_ = std::make_unique<CriteriaScreen>(*model_, std::move(criteria), thresholds_,
                                             settings_.downgrade ? settings_.hysteresis : 0.0);
  restart_screen();
}

void Adaptivity::distribute(const Distribution* distribution) {
  distribution_ = distribution;
  rungs_revision_ = -1;  // which cells can move depends on which this rank owns
  restart_screen();
}

void Adaptivity::find_rungs() {
  rungs_.clear();
  for (const tm_kernel* kernel : Registry::instance().kernels())
    for (std::size_t r = 0; r < settings_.ladder.size(); ++r)
      if (settings_.ladder[r] == kernel->law)
        for (const ElementBlock& block : model_->mesh().blocks)
          if (std::string_view(block.element->name) == kernel->element) {
            rungs_.emplace_back(kernel, static_cast<int>(r));
            break;
          }
}

void Adaptivity::follow(Model& model, const Assembler& assembler, std::span<const int> origin) {
  check_ladder(settings_.ladder, model);
  if (origin.size() != static_cast<std::size_t>(model.cell_count()))
    throw std::invalid_argument("Adaptivity::follow: " + std::to_string(origin.size()) + " origins for " +
                                std::to_string(model.cell_count()) + " cells");
  const int old_cells = static_cast<int>(calm_evaluations_.size());
  for (int source : origin)
    if (source < 0 || source >= old_cells)
      throw std::invalid_argument("Adaptivity::follow: origin " + std::to_string(source) + " is not an old cell");
  const auto carry = [&](auto& values) {
    std::remove_reference_t<decltype(values)> carried;
    carried.reserve(origin.size());
    for (int source : origin) carried.push_back(values[static_cast<std::size_t>(source)]);
    values = std::move(carried);
  };
  for (std::vector<double>& values : values_) carry(values);
  carry(calm_evaluations_);
  carry(initial_rungs_);
  model_ = &model;
  assembler_ = &assembler;
  find_rungs();
  nodal_forces_.clear();
  moves_.clear();
  cell_rungs_.clear();
  rungs_revision_ = -1;  // read the rungs from the new model's kernels at the next evaluation
  make_screen();         // the carried values are the refreshed ones (share_values before the new mesh)
}

AdaptivityMemory Adaptivity::memory() const {
  refresh_values();
  return {calm_evaluations_, values_, total_switches_, criteria_seconds_, criterion_seconds_, records_, last_record_};
}

void Adaptivity::restore(AdaptivityMemory memory) {
  if (memory.calm_evaluations.size() != calm_evaluations_.size() || memory.values.size() != values_.size() ||
      memory.criterion_seconds.size() != criterion_seconds_.size())
    throw std::invalid_argument("Adaptivity::restore: saved for another model or other criteria");
  for (std::size_t c = 0; c < values_.size(); ++c)
    if (memory.values[c].size() != values_[c].size())
      throw std::invalid_argument("Adaptivity::restore: saved for another model");
  calm_evaluations_ = std::move(memory.calm_evaluations);
  values_ = std::move(memory.values);
  total_switches_ = memory.total_switches;
  criteria_seconds_ = memory.criteria_seconds;
  criterion_seconds_ = std::move(memory.criterion_seconds);
  records_ = std::move(memory.records);
  last_record_ = std::move(memory.last_record);
  stale_ = false;
  restart_screen();
}

void Adaptivity::advance_blends() {
  if (settings_.blend_steps <= 0) return;
  const double increment = 1.0 / settings_.blend_steps;
  for (int cell = 0; cell < model_->cell_count(); ++cell)
    if (model_->blend_from(cell)) model_->set_blend_weight(cell, model_->blend_weight(cell) + increment);
}

int Adaptivity::rung_of(const tm_kernel& kernel) const {
  // Every kernel a cell can hold under a ladder law is listed (a few): a
  // linear search by address beats comparing names per cell, and the list
  // is never written after construction (cells are decided in parallel).
  for (const auto& [known, rung] : rungs_)
    if (known == &kernel) return rung;
  return -1;
}

bool Adaptivity::fails_above(int cell, int rung) const {
  for (std::size_t c = 0; c < criteria_.size(); ++c) {
    if (target_rungs_[c] <= rung) continue;
    const double value = values_[c][cell];
    // Criterion::fails, without a virtual call per cell.
    if (quality_[c] ? value < thresholds_[c] : value >= thresholds_[c]) return true;
  }
  return false;
}

bool Adaptivity::calm_at(int cell, int rung) const {
  // Within threshold x hysteresis (quality criteria: above threshold / hysteresis).
  for (std::size_t c = 0; c < criteria_.size(); ++c) {
    if (target_rungs_[c] < rung) continue;  // asks for a lower law: does not hold the cell here
    const double value = values_[c][cell];
    const bool calm =
        quality_[c] ? value >= thresholds_[c] / settings_.hysteresis : value <= thresholds_[c] * settings_.hysteresis;
    if (!calm) return false;
  }
  return true;
}

void Adaptivity::switch_law(int cell, const std::string& law) {
  const tm_kernel* before = &model_->kernel(cell);
  model_->set_law(cell, law);
  if (settings_.blend_steps > 0) model_->start_blend(cell, before);
}

int Adaptivity::start(std::span<const double> u) {
  if (criteria_.empty()) return 0;
  const auto begin = std::chrono::steady_clock::now();
  const int blend_steps = settings_.blend_steps;
  settings_.blend_steps = 0;  // before the first step there is nothing to blend from
  AdaptivityRecord record;
  record.step = 0;
  for (std::size_t pass = 0; pass + 1 < settings_.ladder.size(); ++pass) {
    const int before = record.upgrades;
    assess(u, record);
    if (record.upgrades == before) break;
  }
  settings_.blend_steps = blend_steps;
  criteria_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  if (record.upgrades == 0) return 0;
  records_.add(record);
  last_record_ = std::move(record);
  return last_record_.upgrades;
}

int Adaptivity::update(std::span<const double> u, int step) {
  if (criteria_.empty() || step % settings_.every != 0) return 0;
  const auto start = std::chrono::steady_clock::now();
  AdaptivityRecord record;
  record.step = step;
  assess(u, record);
  records_.add(record);
  last_record_ = std::move(record);
  criteria_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return last_record_.upgrades + last_record_.downgrades;
}

/// The cells' rungs, read again from their kernels when the model's laws
/// changed other than by this object's switches (set_law from a script, a
/// checkpoint restored, a blend ended).
void Adaptivity::refresh_rungs() {
  if (rungs_revision_ == model_->law_revision()) return;
  const int cells = model_->cell_count();
  cell_rungs_.resize(cells);
  if (movable_.size() != static_cast<std::size_t>(cells)) restart_screen();
  movable_.resize(cells, kStill);
  cells_per_rung_.assign(settings_.ladder.size(), 0);
  off_ladder_cells_ = 0;
  for (int cell = 0; cell < cells; ++cell) {
    const int rung = rung_of(model_->kernel(cell));
    cell_rungs_[cell] = static_cast<signed char>(rung);
    set_movable(cell, can_move(cell, rung) ? kMustDecide : kStill);
    if (!counts(cell)) continue;
    if (rung >= 0) ++cells_per_rung_[rung];
    else ++off_ladder_cells_;
  }
  rungs_revision_ = model_->law_revision();
}

void Adaptivity::restart_screen() {
  if (!screen_) return;
  screen_->reset();
  screen_warming_ = true;
  screen_pause_ = 0;
}

CriteriaScreen* Adaptivity::screen_now() {
  if (!screen_) return nullptr;
  if (screen_pause_ == 0) return screen_.get();
  if (--screen_pause_ == 0) restart_screen();  // the screen's slacks are stale after the pause
  return nullptr;
}

void Adaptivity::judge_screen(long evaluated) {
  if (screen_warming_) {  // every movable cell was evaluated to start the slacks: says nothing
    screen_warming_ = false;
    return;
  }
  if (evaluated > kScreenBusyShare * model_->cell_count()) screen_pause_ = kScreenPause;
}

void Adaptivity::set_movable(int cell, unsigned char state) {
  // A still cell's values were not kept up to date: evaluate it once it can move.
  if (screen_ && movable_[cell] == kStill && state != kStill) screen_->forget(cell);
  movable_[cell] = state;
}

bool Adaptivity::counts(int cell) const { return !distribution_ || distribution_->owns_cell(cell); }

bool Adaptivity::can_move(int cell, int rung) const {
  if (distribution_ && !distribution_->owns_cell(cell)) return false;
  const int initial = initial_rungs_[cell];
  if (rung < 0 || initial < 0) return false;
  return rung < top_target_ || (settings_.downgrade && rung > initial);
}

/// The move of one cell after its criteria were evaluated: +1 (climb), -1
/// (descend) or 0; updates its calm count.
signed char Adaptivity::decide(int cell, int rung) {
  const int initial = initial_rungs_[cell];
  if (rung < 0 || initial < 0) return 0;  // a law off the ladder never switches
  if (fails_above(cell, rung)) {
    calm_evaluations_[cell] = 0;
    return 1;
  }
  if (!settings_.downgrade || rung <= initial) return 0;
  calm_evaluations_[cell] = calm_at(cell, rung) ? calm_evaluations_[cell] + 1 : 0;
  if (calm_evaluations_[cell] < settings_.calm_steps) return 0;
  calm_evaluations_[cell] = 0;
  return -1;
}

void Adaptivity::evaluate_criteria(const ElementBlock& block, std::span<const double> u, const unsigned char* flags,
                                   std::vector<double>& seconds) const {
  const bool timing = omp_get_thread_num() == 0;
  for (std::size_t c = 0; c < criteria_.size(); ++c) {
    const auto start = std::chrono::steady_clock::now();
    criteria_[c]->evaluate_block({*model_, block, u, nodal_forces_, distribution_, flags}, values_[c]);
    if (timing) seconds[c] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
}

/// One parallel pass over the cells, block by block: every criterion on the
/// block's cells (each criterion's loop compiled for the block's shape),
/// then each cell's move, counted per rung. With the screen, the nodes'
/// motion is measured first (the one barrier before the end), and each
/// block's cells are flagged: only those whose values may have crossed a
/// boundary are evaluated; the others decide on their kept values, which
/// lie on the same side of every boundary. The loops of a block share one
/// static schedule, so a thread evaluates and decides the cells it flagged
/// with no barrier between them (each barrier is a futex wait under the
/// passive wait policy). Then the cells that move switch, in cell order.
void Adaptivity::assess(std::span<const double> u, AdaptivityRecord& record) {
  if (needs_force_) {
    nodal_forces_.resize(model_->dof_count());
    assembler_->assemble(u, nodal_forces_, nullptr);
  }
  const int cells = model_->cell_count();
  moves_.assign(cells, 0);
  refresh_rungs();
  CriteriaScreen* screen = screen_now();
  const long evaluated_before = screen ? screen->evaluated_cells() : 0;
  if (screen) screen_flags_.resize(cells);
  const unsigned char* flags = screen ? screen_flags_.data() : nullptr;
  std::vector<double> seconds(criteria_.size(), 0.0);  // the first thread's share of each criterion
  int moved = 0;
#pragma omp parallel if (cells >= kParallelCells) reduction(+ : moved)
  {
    if (screen) screen->select(u, movable_, screen_flags_);
    for (const ElementBlock& block : model_->mesh().blocks) {
      evaluate_criteria(block, u, flags, seconds);
#pragma omp for schedule(static) nowait
      for (int local = 0; local < block.count(); ++local) moved += decide_cell(block.first_cell + local, flags);
    }
  }
  stale_ = screen != nullptr;
  if (screen) judge_screen(screen->evaluated_cells() - evaluated_before);
  for (std::size_t c = 0; c < criteria_.size(); ++c) criterion_seconds_[c] += seconds[c];
  if (distribution_) share_decisions();
  if (moved > 0 || distribution_) switch_moved_cells(record);
  rungs_revision_ = model_->law_revision();  // the switches above are in cell_rungs_ already
  record_cells_per_law(record);
}

/// Counts of this rank's cells per rung, and off the ladder, summed over the ranks.
void Adaptivity::record_cells_per_law(AdaptivityRecord& record) const {
  std::vector<double> counted(cells_per_rung_.begin(), cells_per_rung_.end());
  counted.push_back(off_ladder_cells_);
  if (distribution_) parallel::sum_over_ranks(counted);
  if (counted.back() > 0) return record_laws(record);  // laws outside the ladder: count them all by name
  std::map<std::string, int> per_law;
  for (std::size_t r = 0; r + 1 < counted.size(); ++r)
    if (counted[r] > 0) per_law[settings_.ladder[r]] += static_cast<int>(counted[r]);
  record.cells_per_law.assign(per_law.begin(), per_law.end());
}

int Adaptivity::decide_cell(int cell, const unsigned char* flags) {
  const unsigned char state = movable_[cell];
  if (state == kStill) return 0;  // also another rank's cell
  const bool evaluated = !flags || flags[cell] == kScreenEvaluate;
  if (flags && evaluated) screen_->settle(cell, values_);
  if (!evaluated && state == kQuiet) return 0;  // the same values, rung and answer as last time
  const signed char move = moves_[cell] = decide(cell, cell_rungs_[cell]);
  movable_[cell] = move == 0 && !settings_.downgrade ? kQuiet : kMustDecide;
  return move != 0;
}

void Adaptivity::switch_moved_cells(AdaptivityRecord& record) {
  // Counted on the cells' owners (every cell on one process), summed over the ranks.
  double moves[2] = {0, 0};  // upgrades, downgrades
  for (int cell = 0; cell < model_->cell_count(); ++cell) {
    const int move = moves_[cell];
    if (move == 0) continue;
    if (counts(cell)) {
      moves[0] += move > 0;
      moves[1] += move < 0;
      --cells_per_rung_[cell_rungs_[cell]];
      ++cells_per_rung_[cell_rungs_[cell] + move];
    }
    cell_rungs_[cell] = static_cast<signed char>(cell_rungs_[cell] + move);
    set_movable(cell, can_move(cell, cell_rungs_[cell]) ? kMustDecide : kStill);
    switch_law(cell, settings_.ladder[cell_rungs_[cell]]);
  }
  if (distribution_) parallel::sum_over_ranks(moves);
  record.upgrades += static_cast<int>(moves[0]);
  record.downgrades += static_cast<int>(moves[1]);
  total_switches_ += static_cast<int>(moves[0] + moves[1]);
}

void Adaptivity::refresh_values() const {
  if (!stale_) return;
  const auto begin = std::chrono::steady_clock::now();
  std::vector<double> seconds(criteria_.size(), 0.0);
#pragma omp parallel if (model_->cell_count() >= kParallelCells)
  for (const ElementBlock& block : model_->mesh().blocks)
    evaluate_criteria(block, screen_->last_displacement(), nullptr, seconds);
  stale_ = false;
  criteria_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
}

void Adaptivity::share_decisions() {
  // What each owner decided, a double per cell: 4 x its calm count + its
  // move + 1 (exact).
  const int cells = model_->cell_count();
  std::vector<double> decided(cells, 0.0);
  for (int cell = 0; cell < cells; ++cell) decided[cell] = 4.0 * calm_evaluations_[cell] + moves_[cell] + 1;
  distribution_->share_cell_values(decided);
  for (int cell = 0; cell < cells; ++cell) {
    const long packed = std::lround(decided[cell]);
    moves_[cell] = static_cast<signed char>(packed % 4 - 1);
    calm_evaluations_[cell] = static_cast<int>(packed / 4);
  }
}

void Adaptivity::share_values() {
  refresh_values();
  if (!distribution_) return;
  for (std::vector<double>& values : values_) distribution_->share_cell_values(values);
}

void Adaptivity::record_laws(AdaptivityRecord& record) const {
  // Per law of the model's list (the same on every rank), this rank's cells.
  const std::vector<std::string>& laws = model_->law_names();
  std::vector<std::pair<const tm_kernel*, int>> per_kernel;  // few distinct kernels
  for (int cell = 0; cell < model_->cell_count(); ++cell) {
    if (!counts(cell)) continue;
    const tm_kernel* kernel = &model_->kernel(cell);
    auto found = std::find_if(per_kernel.begin(), per_kernel.end(), [&](const auto& p) { return p.first == kernel; });
    if (found == per_kernel.end()) per_kernel.emplace_back(kernel, 1);
    else ++found->second;
  }
  std::vector<double> per_law(laws.size(), 0.0);
  for (const auto& [kernel, count] : per_kernel)
    per_law[std::find(laws.begin(), laws.end(), kernel->law) - laws.begin()] += count;
  if (distribution_) parallel::sum_over_ranks(per_law);
  std::map<std::string, int> named;
  for (std::size_t law = 0; law < laws.size(); ++law)
    if (per_law[law] > 0) named[laws[law]] = static_cast<int>(per_law[law]);
  record.cells_per_law.assign(named.begin(), named.end());
}

std::vector<io::Field> Adaptivity::cell_fields() const {
  refresh_values();
  std::vector<io::Field> fields;
  for (std::size_t c = 0; c < criteria_.size(); ++c) fields.push_back({names_[c], 1, values_[c]});
  io::Field state{"state", 1, std::vector<double>(model_->cell_count(), 0.0)};
  for (int cell = 0; cell < model_->cell_count(); ++cell) {
    if (&model_->kernel(cell) != &model_->initial_kernel(cell)) {
      state.values[cell] = 2.0;
      continue;
    }
    double worst = 0.0;
    for (std::size_t c = 0; c < criteria_.size(); ++c) {
      const double value = values_[c][cell], threshold = thresholds_[c];
      double ratio;
      if (criteria_[c]->is_quality()) ratio = value > 0 ? threshold / value : 1.0;
      else ratio = threshold > 0 ? value / threshold : (value > 0 ? 1.0 : 0.0);
      worst = std::max(worst, std::min(ratio, 1.0));
    }
    state.values[cell] = worst;
  }
  fields.push_back(std::move(state));
  return fields;
}

}  // namespace tensormass
