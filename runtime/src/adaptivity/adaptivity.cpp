#include "tensormass/adaptivity/adaptivity.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string_view>

#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass {

namespace {
constexpr int kMaxDofs = 81;
constexpr int kParallelCells = 4096;  // below this a parallel region costs more than it saves

/// Every ladder law must have a kernel for every element type of the mesh.
void check_ladder(const std::vector<std::string>& ladder, const Mesh& mesh) {
  if (ladder.size() < 2) throw std::invalid_argument("an adaptivity ladder needs at least two laws");
  for (const std::string& law : ladder)
    for (const ElementBlock& block : mesh.blocks)
      if (!Registry::instance().find(law, block.element->name, "whole"))
        throw std::invalid_argument("adaptivity ladder: no kernel for law '" + law + "' on " + block.element->name);
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
  check_ladder(settings.ladder, model.mesh());
  for (const CriterionSpec& criterion : settings.criteria) {
    criteria_.push_back(make_criterion(criterion.name));
    thresholds_.push_back(criterion.threshold);
    target_rungs_.push_back(target_rung(criterion, settings.ladder));
    names_.push_back(criterion.name);
    needs_force_ = needs_force_ || criteria_.back()->needs_force();
  }
  values_.assign(criteria_.size(), std::vector<double>(model.cell_count(), 0.0));
  criterion_seconds_.assign(criteria_.size(), 0.0);
  calm_evaluations_.assign(model.cell_count(), 0);
}

AdaptivityMemory Adaptivity::memory() const {
  return {calm_evaluations_, values_, total_switches_, criteria_seconds_, criterion_seconds_, records_};
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
}

void Adaptivity::advance_blends() {
  if (settings_.blend_steps <= 0) return;
  const double increment = 1.0 / settings_.blend_steps;
  for (int cell = 0; cell < model_->cell_count(); ++cell)
    if (model_->blend_from(cell)) model_->set_blend_weight(cell, model_->blend_weight(cell) + increment);
}

void Adaptivity::evaluate(std::span<const double> u) {
  if (needs_force_) {
    nodal_forces_.resize(model_->dof_count());
    assembler_->assemble(u, nodal_forces_, nullptr);
  }
  // One pass per criterion, so that each keeps its own running time.
  for (std::size_t c = 0; c < criteria_.size(); ++c) {
    const auto start = std::chrono::steady_clock::now();
    for (const ElementBlock& block : model_->mesh().blocks) evaluate_block(*criteria_[c], block, u, values_[c]);
    criterion_seconds_[c] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
}

void Adaptivity::evaluate_block(const Criterion& criterion, const ElementBlock& block, std::span<const double> u,
                                std::vector<double>& values) const {
  const Model& model = *model_;
  const Mesh& mesh = model.mesh();
  const int d = model.dim();
  const bool rest_needed = criterion.needs_rest(), force_needed = criterion.needs_force();
  // Each cell's value depends on that cell alone: any thread count gives the same values.
#pragma omp parallel if (block.count() >= kParallelCells)
  {
    double rest[kMaxDofs], local_u[kMaxDofs], force[kMaxDofs];
#pragma omp for schedule(static)
    for (int local = 0; local < block.count(); ++local) {
      const int cell = block.first_cell + local;
      if (rest_needed) {
        const auto nodes = model.cell_nodes(cell);
        for (std::size_t j = 0; j < nodes.size(); ++j)
          for (int a = 0; a < d; ++a) rest[j * d + a] = mesh.rest_positions[3 * nodes[j] + a];
      }
      model.gather(cell, u, local_u);
      if (force_needed) model.gather(cell, nodal_forces_, force);
      const ElementView view{*block.element, model.kernel(cell), model.consts(cell), rest, local_u, force, d};
      values[cell] = criterion.evaluate(view);
    }
  }
}

int Adaptivity::rung_of(const tm_kernel& kernel) const {
  // A handful of distinct kernels: a linear search by address beats comparing names per cell.
  for (const auto& [known, rung] : rung_cache_)
    if (known == &kernel) return rung;
  const std::string_view law = kernel.law;
  int rung = -1;
  for (std::size_t r = 0; r < settings_.ladder.size(); ++r)
    if (settings_.ladder[r] == law) rung = static_cast<int>(r);
  rung_cache_.emplace_back(&kernel, rung);
  return rung;
}

bool Adaptivity::fails_above(int cell, int rung) const {
  for (std::size_t c = 0; c < criteria_.size(); ++c)
    if (target_rungs_[c] > rung && criteria_[c]->fails(values_[c][cell], thresholds_[c])) return true;
  return false;
}

bool Adaptivity::calm_at(int cell, int rung) const {
  // Within threshold x hysteresis (quality criteria: above threshold / hysteresis).
  for (std::size_t c = 0; c < criteria_.size(); ++c) {
    if (target_rungs_[c] < rung) continue;  // asks for a lower law: does not hold the cell here
    const double value = values_[c][cell];
    const bool calm = criteria_[c]->is_quality() ? value >= thresholds_[c] / settings_.hysteresis
                                                 : value <= thresholds_[c] * settings_.hysteresis;
    if (!calm) return false;
  }
  return true;
}

void Adaptivity::switch_law(int cell, const std::string& law) {
  const tm_kernel* before = &model_->kernel(cell);
  model_->set_law(cell, law);
  if (settings_.blend_steps > 0) model_->start_blend(cell, before);
  ++total_switches_;
}

int Adaptivity::start(std::span<const double> u) {
  if (criteria_.empty()) return 0;
  const auto begin = std::chrono::steady_clock::now();
  const int blend_steps = settings_.blend_steps;
  settings_.blend_steps = 0;  // before the first step there is nothing to blend from
  AdaptivityRecord record;
  record.step = 0;
  for (std::size_t pass = 0; pass + 1 < settings_.ladder.size(); ++pass) {
    evaluate(u);
    const int before = record.upgrades;
    switch_laws(record);
    if (record.upgrades == before) break;
  }
  settings_.blend_steps = blend_steps;
  criteria_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  if (record.upgrades == 0) return 0;
  record_laws(record);
  records_.push_back(record);
  return record.upgrades;
}

int Adaptivity::update(std::span<const double> u, int step) {
  if (criteria_.empty() || step % settings_.every != 0) return 0;
  const auto start = std::chrono::steady_clock::now();
  evaluate(u);
  AdaptivityRecord record;
  record.step = step;
  switch_laws(record);
  record_laws(record);
  records_.push_back(record);
  criteria_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return record.upgrades + record.downgrades;
}

void Adaptivity::switch_laws(AdaptivityRecord& record) {
  for (int cell = 0; cell < model_->cell_count(); ++cell) {
    const int rung = rung_of(model_->kernel(cell)), initial = rung_of(model_->initial_kernel(cell));
    if (rung < 0 || initial < 0) continue;  // a law off the ladder never switches
    if (fails_above(cell, rung)) {
      calm_evaluations_[cell] = 0;
      switch_law(cell, settings_.ladder[rung + 1]);
      ++record.upgrades;
    } else if (settings_.downgrade && rung > initial) {
      calm_evaluations_[cell] = calm_at(cell, rung) ? calm_evaluations_[cell] + 1 : 0;
      if (calm_evaluations_[cell] >= settings_.calm_steps) {
        switch_law(cell, settings_.ladder[rung - 1]);
        calm_evaluations_[cell] = 0;
        ++record.downgrades;
      }
    }
  }
}

void Adaptivity::record_laws(AdaptivityRecord& record) {
  std::vector<std::pair<const tm_kernel*, int>> per_kernel;  // few distinct kernels
  for (int cell = 0; cell < model_->cell_count(); ++cell) {
    const tm_kernel* kernel = &model_->kernel(cell);
    auto found = std::find_if(per_kernel.begin(), per_kernel.end(), [&](const auto& p) { return p.first == kernel; });
    if (found == per_kernel.end()) per_kernel.emplace_back(kernel, 1);
    else ++found->second;
  }
  std::map<std::string, int> per_law;
  for (const auto& [kernel, count] : per_kernel) per_law[kernel->law] += count;
  record.cells_per_law.assign(per_law.begin(), per_law.end());
}

std::vector<io::Field> Adaptivity::cell_fields() const {
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
