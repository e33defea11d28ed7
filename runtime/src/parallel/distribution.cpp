#include "tensormass/parallel/distribution.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

#include "tensormass/parallel/mpi_world.hpp"

namespace tensormass {

namespace {

void check_ranks(int rank, int size) {
  if (size < 1 || rank < 0 || rank >= size)
    throw std::invalid_argument("Distribution: rank " + std::to_string(rank) + " of " + std::to_string(size));
}

/// The cut of a model holding the whole mesh: every cell its own global index.
CellCut whole_mesh_cut(const Model& model, std::vector<int> cell_owner, int size) {
  if (static_cast<int>(cell_owner.size()) != model.cell_count())
    throw std::invalid_argument("Distribution: " + std::to_string(cell_owner.size()) + " cell owners for " +
                                std::to_string(model.cell_count()) + " cells");
  CellCut cut;
  cut.node_owner = parallel::node_owners(model.mesh(), cell_owner, size);
  cut.global_cell.resize(cell_owner.size());
  std::iota(cut.global_cell.begin(), cut.global_cell.end(), 0);
  cut.cell_owner = std::move(cell_owner);
  cut.whole_cell_count = model.cell_count();
  return cut;
}

}  // namespace

Distribution::Distribution(const Model& model, std::vector<int> cell_owner, int rank, int size)
    : model_(&model), rank_(rank), size_(size) {
  check_ranks(rank, size);
  cut_ = whole_mesh_cut(model, std::move(cell_owner), size);
  build();
}

Distribution::Distribution(const Model& model, CellCut cut, int rank, int size)
    : model_(&model), rank_(rank), size_(size), holds_part_(true), cut_(std::move(cut)) {
  check_ranks(rank, size);
  const std::size_t cells = static_cast<std::size_t>(model.cell_count());
  const std::size_t nodes = static_cast<std::size_t>(model.mesh().node_count());
  if (cut_.global_cell.size() != cells || cut_.cell_owner.size() != cells || cut_.node_owner.size() != nodes ||
      cut_.global_node.size() != nodes)
    throw std::invalid_argument("Distribution: a cut of " + std::to_string(cut_.global_cell.size()) + " cells and " +
                                std::to_string(cut_.global_node.size()) + " nodes for a model of " +
                                std::to_string(cells) + " cells and " + std::to_string(nodes) + " nodes");
  const auto increasing_below = [](const std::vector<int>& numbers, int count) {
    for (std::size_t i = 0; i < numbers.size(); ++i)
      if (numbers[i] < 0 || numbers[i] >= count || (i > 0 && numbers[i] <= numbers[i - 1])) return false;
    return true;
  };
  if (!increasing_below(cut_.global_cell, cut_.whole_cell_count))
    throw std::invalid_argument("Distribution: the cut's global cell numbers are not increasing within the mesh");
  if (!increasing_below(cut_.global_node, cut_.whole_node_count))
    throw std::invalid_argument("Distribution: the cut's global node numbers are not increasing within the mesh");
  build();
}

void Distribution::build() {
  const int d = model_->dim();
  for (std::size_t cell = 0; cell < cut_.cell_owner.size(); ++cell)
    if (cut_.cell_owner[cell] < 0 || cut_.cell_owner[cell] >= size_)
      throw std::invalid_argument("Distribution: cell " + std::to_string(cell) + " owned by rank " +
                                  std::to_string(cut_.cell_owner[cell]));
  assembled_.assign(model_->cell_count(), 0);
  for (int cell = 0; cell < model_->cell_count(); ++cell) {
    bool touches = owns_cell(cell);
    for (int node : model_->cell_nodes(cell)) touches = touches || owns_node(node);
    assembled_[cell] = touches;
    assembled_count_ += touches;
  }
  const auto& free = model_->free_dofs();
  for (std::size_t row = 0; row < free.size(); ++row)
    (node_owner(free[row] / d) == rank_ ? owned_free_rows_ : foreign_free_rows_).push_back(static_cast<int>(row));
  if (!holds_part_) number_whole_mesh_rows();
  for (std::size_t node = 0; node < cut_.node_owner.size(); ++node)
    (cut_.node_owner[node] != rank_ ? foreign_nodes_ : own_nodes_).push_back(static_cast<int>(node));
  if (holds_part_) build_ghost_links();
}

void Distribution::number_whole_mesh_rows() {
  // Free dofs numbered rank by rank, each rank's in ascending free order.
  const int d = model_->dim();
  const auto& free = model_->free_dofs();
  std::vector<int> rows_of_rank(size_ + 1, 0);
  for (int dof : free) ++rows_of_rank[node_owner(dof / d) + 1];
  for (int r = 0; r < size_; ++r) rows_of_rank[r + 1] += rows_of_rank[r];
  first_global_row_ = rows_of_rank[rank_];
  global_row_count_ = static_cast<int>(free.size());
  global_row_.resize(free.size());
  std::vector<int> next(rows_of_rank.begin(), rows_of_rank.end() - 1);
  for (std::size_t row = 0; row < free.size(); ++row) global_row_[row] = next[node_owner(free[row] / d)]++;
}

void Distribution::number_global_rows() {
  if (!holds_part_) return;
  std::vector<double> rows_of_rank(size_, 0.0);
  rows_of_rank[rank_] = static_cast<double>(owned_free_rows_.size());
  parallel::sum_over_ranks(rows_of_rank);
  first_global_row_ = static_cast<int>(std::accumulate(rows_of_rank.begin(), rows_of_rank.begin() + rank_, 0.0));
  global_row_count_ = static_cast<int>(std::accumulate(rows_of_rank.begin(), rows_of_rank.end(), 0.0));
  const std::size_t free_count = model_->free_dofs().size();
  std::vector<double> row(free_count, -1.0);  // ghost rows from their owners, as doubles (exact below 2^53)
  for (std::size_t i = 0; i < owned_free_rows_.size(); ++i) row[owned_free_rows_[i]] = first_global_row_ + i;
  share_ghost_free(row);
  global_row_.assign(row.begin(), row.end());
  // The whole mesh's free order: a flag per whole dof from its owner, then a running count.
  const int d = model_->dim();
  const auto& free_index = model_->free_index();
  std::vector<double> index(static_cast<std::size_t>(d) * cut_.whole_node_count, 0.0);
  for (int node : own_nodes_)
    for (int a = 0; a < d; ++a) index[d * global_node(node) + a] = free_index[node * d + a] >= 0;
  parallel::sum_over_ranks(index);
  double count = 0.0;
  for (double& entry : index) std::swap(entry, count), count += entry;  // entry: free dofs before it
  std::fill(row.begin(), row.end(), -1.0);
  for (int r : owned_free_rows_) {
    const int dof = model_->free_dofs()[r];
    row[r] = index[d * global_node(dof / d) + dof % d];
  }
  share_ghost_free(row);
  whole_free_row_.assign(row.begin(), row.end());
}

void Distribution::build_ghost_links() {
  // A rank's part holds every cell touching its nodes, so each rank can
  // tell from its own cells who needs its nodes: rank q needs cell c when q
  // owns c or one of c's nodes, and then needs all of c's nodes. What q
  // sends here is found alike from q's side: the two lists agree.
  std::vector<std::vector<int>> send(size_), receive(size_), send_cells(size_), receive_cells(size_);
  std::vector<int> needing;
  for (int cell = 0; cell < model_->cell_count(); ++cell) {
    const auto nodes = model_->cell_nodes(cell);
    // Rank q holds a cell it does not own when it owns one of its nodes.
    if (!owns_cell(cell)) receive_cells[cell_owner(cell)].push_back(cell);
    else
      for (int node : nodes)
        if (const int q = node_owner(node); q != rank_) send_cells[q].push_back(cell);  // made unique below
    needing.assign(1, cell_owner(cell));
    for (int node : nodes) needing.push_back(node_owner(node));
    for (int node : nodes) {
      if (!owns_node(node)) {
        receive[node_owner(node)].push_back(node);
        continue;
      }
      for (int q : needing)
        if (q != rank_) send[q].push_back(node);
    }
  }
  const int d = model_->dim();
  const auto& free_index = model_->free_index();
  const auto dofs_of = [&](const std::vector<int>& nodes, std::vector<int>& dofs, std::vector<int>& free) {
    for (int node : nodes)
      for (int a = 0; a < d; ++a) {
        dofs.push_back(node * d + a);
        if (free_index[node * d + a] >= 0) free.push_back(free_index[node * d + a]);
      }
  };
  for (int q = 0; q < size_; ++q) {
    for (std::vector<int>* list : {&send[q], &receive[q], &send_cells[q]}) {
      std::sort(list->begin(), list->end());
      list->erase(std::unique(list->begin(), list->end()), list->end());
    }
    if (send[q].empty() && receive[q].empty() && send_cells[q].empty() && receive_cells[q].empty()) continue;
    GhostLink link;
    link.rank = q;
    link.send_nodes = std::move(send[q]);
    link.receive_nodes = std::move(receive[q]);
    link.send_cells = std::move(send_cells[q]);
    link.receive_cells = std::move(receive_cells[q]);
    dofs_of(link.send_nodes, link.send_dofs, link.send_free);
    dofs_of(link.receive_nodes, link.receive_dofs, link.receive_free);
    ghost_nodes_.insert(ghost_nodes_.end(), link.receive_nodes.begin(), link.receive_nodes.end());
    neighbours_.push_back(q);
    links_.push_back(std::move(link));
  }
  std::sort(ghost_nodes_.begin(), ghost_nodes_.end());
  send_buffers_.resize(links_.size());
  receive_buffers_.resize(links_.size());
}

int Distribution::local_cell(int global) const {
  const auto found = std::lower_bound(cut_.global_cell.begin(), cut_.global_cell.end(), global);
  return found != cut_.global_cell.end() && *found == global ? static_cast<int>(found - cut_.global_cell.begin()) : -1;
}

void Distribution::keep_own_dofs(std::span<double> v) const {
  // By node from a list made once: a test per dof with its division by d
  // took 6 % of a 1M-tet explicit step on 2 ranks.
  const std::size_t d = static_cast<std::size_t>(model_->dim());
  if (v.size() != d * cut_.node_owner.size())
    throw std::invalid_argument("Distribution::keep_own_dofs: " + std::to_string(v.size()) + " values for " +
                                std::to_string(d * cut_.node_owner.size()) + " dofs");
  for (int node : foreign_nodes_) std::fill_n(v.begin() + static_cast<std::ptrdiff_t>(d * node), d, 0.0);
}

void Distribution::keep_own_free(std::span<double> v) const {
  if (v.size() != model_->free_dofs().size())
    throw std::invalid_argument("Distribution::keep_own_free: " + std::to_string(v.size()) + " values for " +
                                std::to_string(model_->free_dofs().size()) + " free dofs");
  for (int row : foreign_free_rows_) v[row] = 0.0;
}

void Distribution::complete_dofs(std::span<double> v) const {
  keep_own_dofs(v);
  if (holds_part_) share_ghost_dofs(v);
  else parallel::sum_over_ranks(v);
}

void Distribution::complete_free(std::span<double> v) const {
  keep_own_free(v);
  if (holds_part_) share_ghost_free(v);
  else parallel::sum_over_ranks(v);
}

std::vector<double> Distribution::whole_dofs(std::span<const double> v) const {
  std::vector<double> whole;
  if (!holds_part_) {
    whole.assign(v.begin(), v.end());
    complete_dofs(whole);
    return whole;
  }
  const std::size_t d = static_cast<std::size_t>(model_->dim());
  if (v.size() != d * cut_.node_owner.size())
    throw std::invalid_argument("Distribution::whole_dofs: " + std::to_string(v.size()) + " values for " +
                                std::to_string(d * cut_.node_owner.size()) + " dofs");
  whole.assign(d * cut_.whole_node_count, 0.0);
  for (int node : own_nodes_) std::copy_n(v.begin() + d * node, d, whole.begin() + d * cut_.global_node[node]);
  parallel::sum_over_ranks(whole);
  return whole;
}

std::vector<double> Distribution::whole_free(std::span<const double> v) const {
  std::vector<double> whole;
  if (!holds_part_) {
    whole.assign(v.begin(), v.end());
    complete_free(whole);
    return whole;
  }
  if (v.size() != whole_free_row_.size())
    throw std::invalid_argument("Distribution::whole_free: " + std::to_string(v.size()) + " values for " +
                                std::to_string(whole_free_row_.size()) + " free dofs (rows numbered?)");
  whole.assign(static_cast<std::size_t>(global_row_count_), 0.0);
  for (int r : owned_free_rows_) whole[whole_free_row_[r]] = v[r];
  parallel::sum_over_ranks(whole);
  return whole;
}

std::vector<double> Distribution::local_dofs(std::span<const double> whole) const {
  if (!holds_part_) return {whole.begin(), whole.end()};
  const std::size_t d = static_cast<std::size_t>(model_->dim());
  if (whole.size() != d * cut_.whole_node_count)
    throw std::invalid_argument("Distribution::local_dofs: " + std::to_string(whole.size()) + " values for " +
                                std::to_string(d * cut_.whole_node_count) + " dofs of the whole mesh");
  std::vector<double> v(d * cut_.node_owner.size());
  for (std::size_t node = 0; node < cut_.node_owner.size(); ++node)
    std::copy_n(whole.begin() + d * cut_.global_node[node], d, v.begin() + d * node);
  return v;
}

std::vector<double> Distribution::local_free(std::span<const double> whole) const {
  if (!holds_part_) return {whole.begin(), whole.end()};
  if (whole.size() != static_cast<std::size_t>(global_row_count_) ||
      whole_free_row_.size() != model_->free_dofs().size())
    throw std::invalid_argument("Distribution::local_free: " + std::to_string(whole.size()) + " values for " +
                                std::to_string(global_row_count_) + " free dofs of the whole mesh (rows numbered?)");
  std::vector<double> v(whole_free_row_.size());
  for (std::size_t r = 0; r < v.size(); ++r) v[r] = whole[whole_free_row_[r]];
  return v;
}

const std::vector<int>& Distribution::sent(const GhostLink& link, Entries entries) {
  return entries == Entries::dofs ? link.send_dofs : entries == Entries::free ? link.send_free : link.send_cells;
}

const std::vector<int>& Distribution::received(const GhostLink& link, Entries entries) {
  return entries == Entries::dofs   ? link.receive_dofs
         : entries == Entries::free ? link.receive_free
                                    : link.receive_cells;
}

void Distribution::exchange(std::span<double> a, std::span<double> b, Entries entries) const {
  if (!holds_part_) return;
  const std::size_t length = entries == Entries::dofs   ? model_->dim() * cut_.node_owner.size()
                             : entries == Entries::free ? model_->free_dofs().size()
                                                        : cut_.cell_owner.size();
  static constexpr const char* kNames[] = {"share_ghost_dofs", "share_ghost_free", "share_cell_values"};
  for (std::span<double> v : {a, b})
    if (!v.empty() && v.size() != length)
      throw std::invalid_argument("Distribution::" + std::string(kNames[static_cast<int>(entries)]) + ": " +
                                  std::to_string(v.size()) + " values for " + std::to_string(length));
  const int vectors = b.empty() ? 1 : 2;
  for (std::size_t i = 0; i < links_.size(); ++i) {
    const std::vector<int>& indices = sent(links_[i], entries);
    std::vector<double>& buffer = send_buffers_[i];
    buffer.clear();
    for (std::span<double> v : {a, b})
      for (std::size_t k = 0; k < indices.size() && !v.empty(); ++k) buffer.push_back(v[indices[k]]);
    receive_buffers_[i].resize(vectors * received(links_[i], entries).size());
  }
  parallel::exchange_with_neighbours(neighbours_, send_buffers_, receive_buffers_);
  for (std::size_t i = 0; i < links_.size(); ++i) {
    const std::vector<int>& indices = received(links_[i], entries);
    const double* value = receive_buffers_[i].data();
    for (std::span<double> v : {a, b})
      for (std::size_t k = 0; k < indices.size() && !v.empty(); ++k) v[indices[k]] = *value++;
  }
}

void Distribution::share_ghost_dofs(std::span<double> a, std::span<double> b) const { exchange(a, b, Entries::dofs); }

void Distribution::share_ghost_free(std::span<double> v) const { exchange(v, {}, Entries::free); }

void Distribution::zero_ghost_dofs(std::span<double> v) const {
  const std::size_t d = static_cast<std::size_t>(model_->dim());
  for (int node : ghost_nodes_) std::fill_n(v.begin() + static_cast<std::ptrdiff_t>(d * node), d, 0.0);
}

void Distribution::share_cell_values(std::span<double> values) const {
  if (holds_part_) {
    exchange(values, {}, Entries::cells);
    return;
  }
  // One value per cell of the whole mesh, from its owner alone: the sum
  // over the ranks is exact, the same bits everywhere.
  std::vector<double> whole(static_cast<std::size_t>(cut_.whole_cell_count), 0.0);
  for (std::size_t cell = 0; cell < values.size(); ++cell)
    if (owns_cell(static_cast<int>(cell))) whole[cut_.global_cell[cell]] = values[cell];
  parallel::sum_over_ranks(whole);
  for (std::size_t cell = 0; cell < values.size(); ++cell) values[cell] = whole[cut_.global_cell[cell]];
}

}  // namespace tensormass
