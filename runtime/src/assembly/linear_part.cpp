#include "tensormass/assembly/linear_part.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "tensormass/kernels/registry.hpp"

namespace tensormass {

namespace {
constexpr int kMaxDofs = kMaxCellDofs;
// Below this a parallel region costs more than the product saves: explicit
// Hooke steps on 2 cores ran 0.83x one thread at 1,024 nodes and 1.03x at 490.
constexpr int kParallelNodes = 1000;
/// The product runs over the rows of the nodes folded cells touch when they
/// are fewer than this share of the nodes (a list costs an indirection).
constexpr double kActiveShare = 0.9;

/// The kernel a cell folds with now, or nullptr when it must run its kernel.
const tm_kernel* foldable_kernel(const Model& model, int cell) {
  const tm_kernel& kernel = model.kernel(cell);
  return kernel.linear && kernel.prony_terms == 0 && !model.blend_from(cell) ? &kernel : nullptr;
}
/// One node's row of multiply_blocks<3>, with its 3 x 3 sums held as three
/// vectors: sums[a] lane b is sum[a][b] (lane 3 collects a spare product and
/// is never read). Each lane does multiply_blocks' own arithmetic, so the
/// results are the same bits; a block costs three vector multiply-adds
/// instead of nine scalar ones. Rows 0 and 1 of a block are loaded 4 wide
/// from their first entry (the fourth is the next row's first); row 2 from
/// entry 5, turned so that entries 6 to 8 come first: no load reads past
/// the block.
inline void multiply_row_3(const NodeGraph& graph, const double* blocks, const double* u, double* g, int node) {
  using Lanes = double __attribute__((vector_size(4 * sizeof(double))));
  const auto load = [](const double* p) {
    Lanes v;
    std::memcpy(&v, p, sizeof v);
    return v;
  };
  Lanes sums[3] = {};
  for (int k = graph.row_start[node]; k < graph.row_start[node + 1]; ++k) {
    const double* block = blocks + static_cast<std::size_t>(k) * 9;
    const double* x = u + static_cast<std::size_t>(graph.columns[k]) * 3;
    __builtin_prefetch(block + 16 * 9);
    const Lanes column = {x[0], x[1], x[2], 0.0};
    sums[0] += load(block) * column;
    sums[1] += load(block + 3) * column;
    sums[2] += __builtin_shufflevector(load(block + 5), load(block + 5), 1, 2, 3, 0) * column;
  }
  for (int a = 0; a < 3; ++a) {
    double row = 0.0;
    for (int b = 0; b < 3; ++b) row += sums[a][b];
    g[static_cast<std::size_t>(node) * 3 + a] = row;
  }
}

/// g = K u for d by d blocks on the graph (D fixed so that the block loops
/// unroll). Each node's row sums go into D x D separate sums (one per row
/// and column of the blocks), added at the end: D^2 chains of additions in
/// flight instead of D, which is what bounds this product on meshes that
/// fit in cache (a fixed order: the same bits on any thread count). Blocks
/// 16 ahead are prefetched: out of cache, the hardware prefetcher alone
/// left this loop slower than the one-sum loop (bench runtime --only spmv).
/// `rows`, when not null, lists the nodes whose rows may be non-zero (the
/// others are written 0); null: every node.
template <int D>
void multiply_blocks(const NodeGraph& graph, const double* blocks, const double* u, double* g,
                     const std::vector<int>* rows) {
  const int count = rows ? static_cast<int>(rows->size()) : graph.node_count();
  if (rows) std::fill(g, g + static_cast<std::size_t>(graph.node_count()) * D, 0.0);
#pragma omp parallel for schedule(static) if (count >= kParallelNodes)
  for (int r = 0; r < count; ++r) {
    const int node = rows ? (*rows)[r] : r;
    if constexpr (D == 3) {
      multiply_row_3(graph, blocks, u, g, node);
      continue;
    }
    double sum[D][D] = {};  // sum[a][b]: row a's terms from column b of the blocks
    for (int k = graph.row_start[node]; k < graph.row_start[node + 1]; ++k) {
      const double* block = blocks + static_cast<std::size_t>(k) * D * D;
      const double* x = u + static_cast<std::size_t>(graph.columns[k]) * D;
      __builtin_prefetch(block + 16 * D * D);
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) sum[a][b] += block[a * D + b] * x[b];
    }
    for (int a = 0; a < D; ++a) {
      double row = 0.0;
      for (int b = 0; b < D; ++b) row += sum[a][b];
      g[static_cast<std::size_t>(node) * D + a] = row;
    }
  }
}
}  // namespace

LinearPart::LinearPart(const Model& model, const NodeGraph& graph, const SparseMatrix& free_pattern)
    : model_(&model), graph_(&graph), free_pattern_(&free_pattern), dim_(model.dim()) {
  folded_kernel_.assign(model.cell_count(), nullptr);
  node_folds_.assign(graph.node_count(), 0);
}

void LinearPart::allocate() {
  if (!blocks_.empty()) return;
  blocks_.assign(graph_->columns.size() * dim_ * dim_, 0.0);
}

void LinearPart::pattern_changed() {
  mapped_ = false;
  free_to_block_ = {};
}

void LinearPart::map_free_pattern() const {
  const int d = dim_, d2 = d * d;
  const NodeGraph& graph = *graph_;
  const SparseMatrix& free_pattern = *free_pattern_;
  // Each free non-zero (row dof r, column dof c) is entry (r % d, c % d) of block (r / d, c / d).
  const auto& free_dofs = model_->free_dofs();
  free_to_block_.resize(free_pattern.columns.size());
  for (int row = 0; row < free_pattern.rows; ++row) {
    const int r = free_dofs[row];
    for (int k = free_pattern.row_start[row]; k < free_pattern.row_start[row + 1]; ++k) {
      const int c = free_dofs[free_pattern.columns[k]];
      free_to_block_[k] = graph.position(r / d, c / d) * d2 + (r % d) * d + c % d;
    }
  }
}

int LinearPart::update() {
  const Model& model = *model_;
  if (seen_revision_ == model.law_revision()) return 0;
  seen_revision_ = model.law_revision();
  if (seen_consts_revision_ != model.consts_revision()) {
    // Some cell's constants were recomputed: the K_e it was folded with
    // cannot be subtracted any more, so fold everything afresh.
    seen_consts_revision_ = model.consts_revision();
    std::fill(blocks_.begin(), blocks_.end(), 0.0);
    std::fill(folded_kernel_.begin(), folded_kernel_.end(), nullptr);
    folded_count_ = 0;
    count_node_folds();
  }
  int changed = 0;
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const tm_kernel* now = foldable_kernel(model, cell);
    const tm_kernel* before = folded_kernel_[cell];
    if (now == before) continue;
    if (before) add_cell(cell, *before, -1.0);
    if (now) add_cell(cell, *now, 1.0);
    if ((now != nullptr) != (before != nullptr)) count_cell_fold(cell, now ? 1 : -1);
    folded_kernel_[cell] = now;
    folded_count_ += (now != nullptr) - (before != nullptr);
    ++changed;
  }
  if (changed > 0) list_active_nodes();
  changes_ += changed;
  return changed;
}

void LinearPart::count_node_folds() {
  node_folds_.assign(graph_->node_count(), 0);
  for (int cell = 0; cell < model_->cell_count(); ++cell)
    if (folded_kernel_[cell])
      for (int node : model_->cell_nodes(cell)) ++node_folds_[node];
  list_active_nodes();
}

void LinearPart::count_cell_fold(int cell, int change) {
  for (int node : model_->cell_nodes(cell))
    if ((node_folds_[node] += change) == 0) unfold_node(node);
}

void LinearPart::unfold_node(int node) {
  // No folded cell touches the node any more: its row and column blocks are
  // zero but for the round-off of the subtractions. Zero them exactly.
  const int d2 = dim_ * dim_;
  const NodeGraph& graph = *graph_;
  for (int k = graph.row_start[node]; k < graph.row_start[node + 1]; ++k) {
    std::fill_n(blocks_.begin() + static_cast<std::ptrdiff_t>(k) * d2, d2, 0.0);
    const int mirror = graph.position(graph.columns[k], node);
    std::fill_n(blocks_.begin() + static_cast<std::ptrdiff_t>(mirror) * d2, d2, 0.0);
  }
}

void LinearPart::list_active_nodes() {
  active_nodes_.clear();
  for (int node = 0; node < static_cast<int>(node_folds_.size()); ++node)
    if (node_folds_[node] > 0) active_nodes_.push_back(node);
}

LinearPart::Saved LinearPart::saved() const {
  return {blocks_, folded_kernel_, folded_count_, changes_, seen_consts_revision_ != model_->consts_revision()};
}

void LinearPart::restore(Saved saved) {
  const std::size_t block_count = graph_->columns.size() * dim_ * dim_;
  if ((!saved.blocks.empty() && saved.blocks.size() != block_count) || saved.folded.size() != folded_kernel_.size())
    throw std::invalid_argument("LinearPart::restore: saved for another model");
  if (saved.blocks.empty()) {
    blocks_.clear();  // nothing was folded: allocated again at the first fold
  } else {
    allocate();
    blocks_ = std::move(saved.blocks);
  }
  folded_kernel_ = std::move(saved.folded);
  folded_count_ = saved.folded_count;
  count_node_folds();
  changes_ = saved.changes;
  seen_revision_ = -1;  // compare every cell at the next update()
  seen_consts_revision_ = model_->consts_revision() - (saved.constants_changed ? 1 : 0);
}

void LinearPart::add_cell(int cell, const tm_kernel& kernel, double sign) {
  allocate();
  const int d = dim_, d2 = d * d, dofs = kernel.dofs;
  double zero[kMaxDofs] = {};
  std::vector<double> K(static_cast<std::size_t>(dofs) * dofs);
  kernel.hessian(zero, model_->consts(cell), K.data());  // constant: any u gives the same
  const auto nodes = model_->cell_nodes(cell);
  for (int i = 0; i < kernel.nodes; ++i)
    for (int j = 0; j < kernel.nodes; ++j) {
      double* block = blocks_.data() + static_cast<std::size_t>(graph_->position(nodes[i], nodes[j])) * d2;
      for (int a = 0; a < d; ++a)
        for (int b = 0; b < d; ++b) block[a * d + b] += sign * K[(i * d + a) * dofs + j * d + b];
    }
}

void LinearPart::multiply(std::span<const double> u, std::span<double> g) const {
  // Rows of nodes no folded cell touches hold exact zeros (unfold_node):
  // skipping them changes no bit, and saves the product where few cells are
  // folded (most cells climbed the ladder).
  const bool few = active_nodes_.size() < kActiveShare * static_cast<double>(graph_->node_count());
  const std::vector<int>* rows = few ? &active_nodes_ : nullptr;
  if (dim_ == 2) multiply_blocks<2>(*graph_, blocks_.data(), u.data(), g.data(), rows);
  else multiply_blocks<3>(*graph_, blocks_.data(), u.data(), g.data(), rows);
}

void LinearPart::copy_free(std::span<double> values) const {
  if (!mapped_) map_free_pattern(), mapped_ = true;
  const int count = static_cast<int>(free_to_block_.size());
  for (int k = 0; k < count; ++k) values[k] = blocks_[free_to_block_[k]];
}

}  // namespace tensormass
