#include "simulation/run_refinement.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "tensormass/common/errors.hpp"

namespace tensormass::detail {

RunRefinement::RunRefinement(const RefinementSettings& settings, Mesh original)
    : settings_(settings), hierarchy_(std::move(original)), calm_(hierarchy_.leaf_mesh().cell_count(), 0) {}

bool RunRefinement::changed(int nodes, int cells, const std::vector<int>& levels) const {
  const std::span<const int> now = hierarchy_.leaf_levels();
  return leaf_mesh().node_count() != nodes || leaf_mesh().cell_count() != cells ||
         !std::equal(now.begin(), now.end(), levels.begin(), levels.end());
}

void RunRefinement::carry_calm(const LeafTransfer& transfer) { calm_ = transfer_cell_field<int>(transfer, calm_); }

LeafTransfer RunRefinement::apply(bool coarsen, std::span<const int> cells, int max_level) {
  const int nodes = leaf_mesh().node_count(), count = leaf_mesh().cell_count();
  const std::vector<int> levels(hierarchy_.leaf_levels().begin(), hierarchy_.leaf_levels().end());
  LeafTransfer transfer = coarsen ? hierarchy_.coarsen(cells) : hierarchy_.refine(cells, max_level);
  carry_calm(transfer);
  if (changed(nodes, count, levels)) {
    history_.coarsens.push_back(coarsen ? 1 : 0);
    history_.max_levels.push_back(max_level);
    history_.cells.insert(history_.cells.end(), cells.begin(), cells.end());
    history_.offsets.push_back(static_cast<int>(history_.cells.size()));
  }
  return transfer;
}

SavedRefinement RunRefinement::save() const {
  SavedRefinement saved = history_;
  saved.calm = calm_;
  saved.peak = peak_;
  return saved;
}

void RunRefinement::restore(const SavedRefinement& saved) {
  if (!history_.coarsens.empty()) throw std::logic_error("RunRefinement::restore: the mesh has changed already");
  for (std::size_t k = 0; k < saved.coarsens.size(); ++k) {
    const std::span<const int> cells(saved.cells.data() + saved.offsets[k],
                                     static_cast<std::size_t>(saved.offsets[k + 1] - saved.offsets[k]));
    apply(saved.coarsens[k] != 0, cells, saved.max_levels[k]);
  }
  if (saved.calm.size() != static_cast<std::size_t>(leaf_mesh().cell_count()) ||
      history_.coarsens.size() != saved.coarsens.size())
    throw InputError("checkpoint: its refinement history does not give back a mesh of " +
                     std::to_string(saved.calm.size()) + " cells");
  calm_ = saved.calm;
  peak_ = saved.peak;
}

void RunRefinement::indicator_per_leaf() {
  // A leaf filled by transition cells gets the energy norm over all of
  // them, as if it were one cell: R = sqrt(sum of its pieces' R^2).
  const std::span<const int> owners = hierarchy_.leaf_owners();
  owner_squares_.assign(static_cast<std::size_t>(hierarchy_.hierarchy_size()), 0.0);
  for (std::size_t cell = 0; cell < owners.size(); ++cell)
    owner_squares_[static_cast<std::size_t>(owners[cell])] += indicator_[cell] * indicator_[cell];
  for (std::size_t cell = 0; cell < owners.size(); ++cell)
    indicator_[cell] = std::sqrt(owner_squares_[static_cast<std::size_t>(owners[cell])]);
}

double RunRefinement::merged_estimate(int cell) const {
  const int parent = hierarchy_.hierarchy_cell(hierarchy_.leaf_owners()[static_cast<std::size_t>(cell)]).parent;
  if (parent < 0) return 0;
  const HierarchyCell& cell_parent = hierarchy_.hierarchy_cell(parent);
  double squares = 0;
  for (int k = 0; k < cell_parent.child_count(); ++k) squares += owner_squares_[cell_parent.children[k]];
  // First-order cells: the energy-norm error grows like the cell size, so
  // the merged parent's error is about twice its children's together.
  return 2 * std::sqrt(squares);
}

std::vector<LeafTransfer> RunRefinement::refine(const Model& model, std::span<const double> u) {
  indicator_.resize(model.cell_count());
  zz_.compute(model, u, indicator_);
  indicator_per_leaf();
  const std::vector<int> marked = select_cells_at_threshold(indicator_, settings_.threshold);
  const std::size_t operations = history_.coarsens.size();
  LeafTransfer transfer = apply(false, marked, settings_.max_level);
  if (history_.coarsens.size() == operations) return {};
  return {std::move(transfer)};
}

std::vector<LeafTransfer> RunRefinement::adapt(const Model& model, std::span<const double> u) {
  indicator_.resize(model.cell_count());
  zz_.compute(model, u, indicator_);
  indicator_per_leaf();
  peak_ = std::max(peak_, *std::max_element(indicator_.begin(), indicator_.end()));
  // Hot and calm against the run's peak (0 while nothing was ever loaded:
  // every cell is calm). A cell is calm when its parent, merged back, would
  // be below the calm level too, so that coarsening does not undo itself.
  const double calm_level = settings_.hysteresis * settings_.threshold * peak_;
  std::vector<int> hot;
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const double r = indicator_[static_cast<std::size_t>(cell)];
    if (peak_ > 0 && r >= settings_.threshold * peak_) hot.push_back(cell);
    int& count = calm_[static_cast<std::size_t>(cell)];
    count = peak_ == 0 || (r < calm_level && merged_estimate(cell) < calm_level) ? count + 1 : 0;
  }
  const std::size_t operations = history_.coarsens.size();
  std::vector<LeafTransfer> transfers;
  transfers.push_back(apply(false, hot, settings_.max_level));
  if (settings_.coarsen) {
    std::vector<int> still_calm;
    for (int cell = 0; cell < leaf_mesh().cell_count(); ++cell)
      if (calm_[static_cast<std::size_t>(cell)] >= settings_.calm_steps) still_calm.push_back(cell);
    transfers.push_back(apply(true, still_calm, 0));
  }
  if (history_.coarsens.size() == operations) return {};
  return transfers;
}

}  // namespace tensormass::detail
