#include "simulation/run_refinement.hpp"

#include <algorithm>
#include <cmath>

namespace tensormass::detail {

RunRefinement::RunRefinement(const RefinementSettings& settings, Mesh original)
    : settings_(settings), hierarchy_(std::move(original)), calm_(hierarchy_.leaf_mesh().cell_count(), 0) {}

bool RunRefinement::changed(int nodes, int cells, const std::vector<int>& levels) const {
  const std::span<const int> now = hierarchy_.leaf_levels();
  return leaf_mesh().node_count() != nodes || leaf_mesh().cell_count() != cells ||
         !std::equal(now.begin(), now.end(), levels.begin(), levels.end());
}

void RunRefinement::carry_calm(const LeafTransfer& transfer) { calm_ = transfer_cell_field<int>(transfer, calm_); }

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
  const int nodes = leaf_mesh().node_count(), cells = leaf_mesh().cell_count();
  const std::vector<int> levels(hierarchy_.leaf_levels().begin(), hierarchy_.leaf_levels().end());
  LeafTransfer transfer = hierarchy_.refine(marked, settings_.max_level);
  carry_calm(transfer);
  if (!changed(nodes, cells, levels)) return {};
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
  const int nodes = leaf_mesh().node_count(), cells = leaf_mesh().cell_count();
  const std::vector<int> levels(hierarchy_.leaf_levels().begin(), hierarchy_.leaf_levels().end());
  std::vector<LeafTransfer> transfers;
  transfers.push_back(hierarchy_.refine(hot, settings_.max_level));
  carry_calm(transfers.back());
  if (settings_.coarsen) {
    std::vector<int> still_calm;
    for (int cell = 0; cell < leaf_mesh().cell_count(); ++cell)
      if (calm_[static_cast<std::size_t>(cell)] >= settings_.calm_steps) still_calm.push_back(cell);
    transfers.push_back(hierarchy_.coarsen(still_calm));
    carry_calm(transfers.back());
  }
  if (!changed(nodes, cells, levels)) return {};
  return transfers;
}

}  // namespace tensormass::detail
