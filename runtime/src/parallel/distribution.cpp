#include "tensormass/parallel/distribution.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "tensormass/parallel/mpi_world.hpp"

namespace tensormass {

Distribution::Distribution(const Model& model, std::vector<int> cell_owner, int rank, int size)
    : model_(&model), rank_(rank), size_(size), cell_owner_(std::move(cell_owner)) {
  if (size < 1 || rank < 0 || rank >= size)
    throw std::invalid_argument("Distribution: rank " + std::to_string(rank) + " of " + std::to_string(size));
  if (static_cast<int>(cell_owner_.size()) != model.cell_count())
    throw std::invalid_argument("Distribution: " + std::to_string(cell_owner_.size()) + " cell owners for " +
                                std::to_string(model.cell_count()) + " cells");
  const int nodes = model.mesh().node_count(), d = model.dim();
  node_owner_.assign(nodes, size);
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const int owner = cell_owner_[cell];
    if (owner < 0 || owner >= size)
      throw std::invalid_argument("Distribution: cell " + std::to_string(cell) + " owned by rank " +
                                  std::to_string(owner));
    for (int node : model.cell_nodes(cell)) node_owner_[node] = std::min(node_owner_[node], owner);
  }
  for (int& owner : node_owner_)
    if (owner == size) owner = 0;  // a node in no cell: no rows to speak of, give it to rank 0
  assembled_.assign(model.cell_count(), 0);
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    bool touches = cell_owner_[cell] == rank;
    for (int node : model.cell_nodes(cell)) touches = touches || node_owner_[node] == rank;
    assembled_[cell] = touches;
    assembled_count_ += touches;
  }
  // Free dofs numbered rank by rank, each rank's in ascending free order.
  const auto& free = model.free_dofs();
  std::vector<int> rows_of_rank(size + 1, 0);
  for (int dof : free) ++rows_of_rank[node_owner_[dof / d] + 1];
  for (int r = 0; r < size; ++r) rows_of_rank[r + 1] += rows_of_rank[r];
  first_global_row_ = rows_of_rank[rank];
  global_row_.resize(free.size());
  std::vector<int> next(rows_of_rank.begin(), rows_of_rank.end() - 1);
  for (std::size_t row = 0; row < free.size(); ++row) {
    const int owner = node_owner_[free[row] / d];
    global_row_[row] = next[owner]++;
    if (owner == rank) owned_free_rows_.push_back(static_cast<int>(row));
  }
}

void Distribution::keep_own_dofs(std::span<double> v) const {
  const int d = model_->dim();
  for (std::size_t dof = 0; dof < v.size(); ++dof)
    if (node_owner_[dof / d] != rank_) v[dof] = 0.0;
}

void Distribution::keep_own_free(std::span<double> v) const {
  const int d = model_->dim();
  const auto& free = model_->free_dofs();
  for (std::size_t row = 0; row < v.size(); ++row)
    if (node_owner_[free[row] / d] != rank_) v[row] = 0.0;
}

void Distribution::complete_dofs(std::span<double> v) const {
  keep_own_dofs(v);
  parallel::sum_over_ranks(v);
}

void Distribution::complete_free(std::span<double> v) const {
  keep_own_free(v);
  parallel::sum_over_ranks(v);
}

}  // namespace tensormass
