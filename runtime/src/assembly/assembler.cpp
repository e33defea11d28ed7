#include "tensormass/assembly/assembler.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <functional>

#include "tensormass/assembly/psd_projection.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/parallel/mpi_world.hpp"

namespace tensormass {

namespace {
constexpr int kParallelCells = 4096;
constexpr int kChunkCells = 128;  // fixed: the summation order must not depend on the thread count

/// g = w g_new + (1 - w) g_old (and the same for K) for a blending cell.
void blend_cell(const Model& model, int cell, const double* u, double* g, double* K, double* old_g,
                std::vector<double>& old_K) {
  const tm_kernel& now = model.kernel(cell);
  const tm_kernel& before = *model.blend_from(cell);
  const double w = model.blend_weight(cell);
  const int dofs = now.dofs;
  if (K) {
    old_K.resize(static_cast<std::size_t>(dofs) * dofs);
    now.gradient_hessian(u, model.consts(cell), g, K);
    before.gradient_hessian(u, model.consts(cell), old_g, old_K.data());
    for (int e = 0; e < dofs * dofs; ++e) K[e] = w * K[e] + (1 - w) * old_K[e];
  } else {
    now.gradient(u, model.consts(cell), g);
    before.gradient(u, model.consts(cell), old_g);
  }
  for (int i = 0; i < dofs; ++i) g[i] = w * g[i] + (1 - w) * old_g[i];
}

/// A planned batch's displacements (D*N by W, kernel_abi.h):
/// batch_u[(j * D + a) * W + lane] = u[dofs[j * W + lane] + a], dofs from
/// KernelPlan::dofs. N = 0 reads the node count at run time, W = 0 the
/// width; the common shapes and widths get compile-time loops. With W = 4
/// each entry's 4 lanes are put together in a register and stored at once:
/// the kernel loads them as one vector, which 4 separate stores would make
/// wait until they reached the cache (a failed store-to-load forwarding).
template <int W_, int D, int N>
void pack_lanes(const int* dofs, int nodes, int width, const double* u, double* batch_u) {
  const int W = W_ > 0 ? W_ : width, n = N > 0 ? N : nodes;
  if constexpr (W_ == 4) {
    using Lanes = double __attribute__((vector_size(4 * sizeof(double))));
    for (int j = 0; j < n; ++j) {
      const double *p0 = u + dofs[j * 4], *p1 = u + dofs[j * 4 + 1], *p2 = u + dofs[j * 4 + 2],
                   *p3 = u + dofs[j * 4 + 3];
      for (int a = 0; a < D; ++a) {
        const Lanes lanes = {p0[a], p1[a], p2[a], p3[a]};
        std::memcpy(batch_u + (j * D + a) * 4, &lanes, sizeof lanes);
      }
    }
    return;
  }
  for (int j = 0; j < n; ++j)
    for (int lane = 0; lane < W; ++lane) {
      const double* node_u = u + dofs[j * W + lane];
      for (int a = 0; a < D; ++a) batch_u[(j * D + a) * W + lane] = node_u[a];
    }
}

/// Adds a batch's forces (element by element, D*N each) into the gradient,
/// cell after cell (N = 0: the node count read at run time).
template <int D, int N>
void scatter_lanes(const int* dofs, int nodes, int width, int used, const double* g, double* gradient) {
  const int n = N > 0 ? N : nodes;
  for (int lane = 0; lane < used; ++lane) {
    const double* cell_g = g + static_cast<std::size_t>(lane) * n * D;
    for (int j = 0; j < n; ++j) {
      double* node_gradient = gradient + dofs[j * width + lane];
      for (int a = 0; a < D; ++a) node_gradient[a] += cell_g[j * D + a];
    }
  }
}

/// Calls visit.template operator()<D, N>() for the kernel's shape: the node
/// count at compile time for tet4, tri3 and quad4, N = 0 (read at run time)
/// for the others.
template <typename Visit>
void with_batch_shape(const tm_kernel& kernel, Visit&& visit) {
  switch (kernel.dim * 100 + kernel.nodes) {
    case 304: return visit.template operator()<3, 4>();
    case 203: return visit.template operator()<2, 3>();
    case 204: return visit.template operator()<2, 4>();
    default: return kernel.dim == 3 ? visit.template operator()<3, 0>() : visit.template operator()<2, 0>();
  }
}

/// The energy of one kernel cell: w W_new + (1 - w) W_old while it blends.
double cell_energy(const Model& model, int cell, const double* u) {
  const double energy = model.kernel(cell).energy(u, model.consts(cell));
  const tm_kernel* before = model.blend_from(cell);
  if (!before) return energy;
  const double w = model.blend_weight(cell);
  return w * energy + (1 - w) * before->energy(u, model.consts(cell));
}

}  // namespace

Assembler::Assembler(const Model& model, bool fold_linear_cells, const Distribution* distribution)
    : model_(&model), nodal_(model), viscous_(model), graph_(make_node_graph(model, &nodal_)) {
  if (distribution) refuse_nodal_pressure_over_ranks();
  distribution_ = distribution;
  build_colours();
  if (fold_linear_cells) linear_ = std::make_unique<LinearPart>(model, graph_, pattern_);
}

namespace {

/// How many of a node's d dofs are free.
int free_dofs_of(const std::vector<int>& free_index, int node, int d) {
  return static_cast<int>(
      std::count_if(&free_index[node * d], &free_index[node * d] + d, [](int i) { return i >= 0; }));
}

/// The node blocks of the pattern build_pattern() makes: per node its free
/// rows, and per neighbour with free dofs one run of consecutive columns
/// (its first column; whether all the node's runs have d is kept per node).
/// Nodes whose rows are empty (has_columns false) have no runs.
NodeRuns node_runs(const NodeGraph& graph, const std::vector<int>& free_index, int d,
                   const std::function<bool(int)>& has_columns) {
  NodeRuns runs;
  const int nodes = static_cast<int>(graph.row_start.size()) - 1;
  const auto free_count = [&](int node) { return free_dofs_of(free_index, node, d); };
  const auto first_free = [&](int node) {
    return *std::find_if(&free_index[node * d], &free_index[node * d] + d, [](int i) { return i >= 0; });
  };
  runs.node_row_start.assign(1, 0);
  runs.run_start.assign(1, 0);
  for (int node = 0; node < nodes; ++node) {
    const int rows = free_count(node);
    runs.node_row_start.push_back(runs.node_row_start.back() + rows);
    bool full = true;
    if (rows > 0 && has_columns(node))
      for (int k = graph.row_start[node]; k < graph.row_start[node + 1]; ++k) {
        const int neighbour = graph.columns[k];
        if (const int columns = free_count(neighbour); columns > 0) {
          runs.run_column.push_back(first_free(neighbour));
          full = full && columns == d;
        }
      }
    runs.run_start.push_back(static_cast<int>(runs.run_column.size()));
    runs.full.push_back(static_cast<unsigned char>(full ? d : 0));
  }
  return runs;
}

}  // namespace

bool Assembler::keeps_rows_of(int node) const { return !distribution_ || distribution_->owns_node(node); }

void Assembler::refuse_nodal_pressure_over_ranks() const {
  // A patch's tangent couples two rings of neighbours; the ranks' halos hold one.
  if (!nodal_.empty())
    throw InputError(
        "split: anp (averaged nodal pressure) does not run over MPI ranks yet; run on one process, "
        "or use split: fbar on hexahedra");
}

void Assembler::distribute(const Distribution* distribution) {
  if (distribution) refuse_nodal_pressure_over_ranks();
  distribution_ = distribution;
  plan_key_ = PlanKey{};  // the cells this rank assembles changed
  // Built again for this rank's rows only at the next need; the whole
  // mesh's layout is not kept.
  tangent_layout_ = false;
  pattern_ = SparseMatrix{};
  for (auto* map : {&block_scatter_, &entry_scatter_, &row_length_}) *map = {};
  block_offsets_ = {};
  entry_offsets_ = {};
  if (linear_) linear_->pattern_changed();
}

void Assembler::require_tangent_layout() const {
  if (tangent_layout_) return;
  build_pattern();
  tangent_layout_ = true;
}

void Assembler::build_pattern() const {
  const Model& model = *model_;
  const int d = model.dim();
  const auto& free_index = model.free_index();
  SparseMatrix& m = pattern_;
  m.rows = model.free_dof_count();
  m.row_start.assign(1, 0);
  m.columns.clear();
  m.diagonal.assign(m.rows, -1);
  for (int dof : model.free_dofs()) {
    const int row = free_index[dof];
    const int node = dof / d;
    if (keeps_rows_of(node))
      for (int k = graph_.row_start[node]; k < graph_.row_start[node + 1]; ++k)
        for (int b = 0; b < d; ++b) {
          const int neighbour = graph_.columns[k];
          const int column = free_index[neighbour * d + b];
          if (column < 0) continue;
          if (column == row) m.diagonal[row] = static_cast<int>(m.columns.size());
          m.columns.push_back(column);
        }
    m.row_start.push_back(static_cast<int>(m.columns.size()));
  }
  m.columns.shrink_to_fit();
  m.values.clear();
  m.values.shrink_to_fit();
  m.node_runs = std::make_shared<const NodeRuns>(
      node_runs(graph_, free_index, d, [this](int node) { return keeps_rows_of(node); }));
  build_scatter_map();
}

SparseMatrix Assembler::pattern() const {
  require_tangent_layout();
  SparseMatrix matrix = pattern_;
  matrix.values.assign(pattern_.columns.size(), 0.0);
  return matrix;
}

namespace {

/// Position in m.values of (row, the first free column of `node`), -1 when
/// the row is fixed or the node has no free dof. Free indices grow with the
/// dof, so a node's free columns sit side by side in a sorted row.
int first_position(const SparseMatrix& m, const std::vector<int>& free_index, int row, int node, int d) {
  const int* columns = &free_index[node * d];
  const int* first_free = std::find_if(columns, columns + d, [](int c) { return c >= 0; });
  if (row < 0 || first_free == columns + d) return -1;
  const auto begin = m.columns.begin() + m.row_start[row], end = m.columns.begin() + m.row_start[row + 1];
  return static_cast<int>(std::lower_bound(begin, end, *first_free) - m.columns.begin());
}

}  // namespace

void Assembler::build_scatter_map() const {
  const Model& model = *model_;
  const int d = model.dim();
  const auto& free_index = model.free_index();
  const SparseMatrix& m = pattern_;
  const int nodes = static_cast<int>(free_index.size()) / d;
  row_length_.assign(nodes, 0);
  for (int node = 0; node < nodes; ++node)
    if (const int row = free_index[node * d]; row >= 0) row_length_[node] = m.row_start[row + 1] - m.row_start[row];
  block_offsets_.assign(1, 0);
  entry_offsets_.assign(1, 0);
  block_scatter_.clear();
  entry_scatter_.clear();
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    if (distribution_ && !distribution_->assembles_cell(cell)) {  // another rank's cell: never scattered here
      block_offsets_.push_back(block_scatter_.size());
      entry_offsets_.push_back(entry_scatter_.size());
      continue;
    }
    const auto cn = model.cell_nodes(cell);
    const bool partial = !scatter_by_blocks_ || std::any_of(cn.begin(), cn.end(), [&](int node) {
      const int free = free_dofs_of(free_index, node, d);
      return free > 0 && free < d;
    });
    if (!partial)
      for (int row_node : cn)
        for (int node : cn)
          block_scatter_.push_back(
              keeps_rows_of(row_node) ? first_position(m, free_index, free_index[row_node * d], node, d) : -1);
    else
      for (int i = 0; i < static_cast<int>(cn.size()) * d; ++i) {
        const int row = keeps_rows_of(cn[i / d]) ? free_index[cn[i / d] * d + i % d] : -1;
        for (int node : cn) {
          int position = first_position(m, free_index, row, node, d);
          for (int c = 0; c < d; ++c)
            entry_scatter_.push_back(position >= 0 && free_index[node * d + c] >= 0 ? position++ : -1);
        }
      }
    block_offsets_.push_back(block_scatter_.size());
    entry_offsets_.push_back(entry_scatter_.size());
  }
  block_scatter_.shrink_to_fit();  // pushed without reserving: no spare capacity kept
  entry_scatter_.shrink_to_fit();
}

void Assembler::set_scatter_by_blocks(bool on) {
  if (on == scatter_by_blocks_) return;
  scatter_by_blocks_ = on;
  if (tangent_layout_) build_scatter_map();
}

std::size_t Assembler::scatter_map_bytes() const {
  require_tangent_layout();
  return sizeof(int) * (block_scatter_.size() + entry_scatter_.size() + row_length_.size()) +
         sizeof(std::size_t) * (block_offsets_.size() + entry_offsets_.size());
}

void Assembler::build_colours() {
  // Cells are cut into chunks of consecutive cells (neighbours in a
  // well-numbered mesh), and the chunks are coloured so that no two chunks
  // of a colour share a node. A thread assembles whole chunks in cell order:
  // memory is visited in order, there are few colours (few barriers), and
  // since the chunk size does not depend on the thread count, neither does
  // the order in which any entry is summed.
  const Model& model = *model_;
  const int cells = model.cell_count();
  const int chunks = (cells + kChunkCells - 1) / kChunkCells;
  std::vector<std::vector<int>> node_chunks(model.mesh().node_count());
  for (int cell = 0; cell < cells; ++cell)
    for (int node : model.cell_nodes(cell)) {
      auto& list = node_chunks[node];
      if (list.empty() || list.back() != cell / kChunkCells) list.push_back(cell / kChunkCells);
    }
  std::vector<int> colour(chunks, -1);
  std::vector<int> used_by;  // used_by[c] == chunk: colour c is taken by a neighbour of chunk
  int colours = 0;
  for (int chunk = 0; chunk < chunks; ++chunk) {
    const int end = std::min(cells, (chunk + 1) * kChunkCells);
    for (int cell = chunk * kChunkCells; cell < end; ++cell)
      for (int node : model.cell_nodes(cell))
        for (int other : node_chunks[node])
          if (colour[other] >= 0) used_by[colour[other]] = chunk;
    int c = 0;
    while (c < colours && used_by[c] == chunk) ++c;
    if (c == colours) {
      ++colours;
      used_by.push_back(-1);
    }
    colour[chunk] = c;
  }
  colour_start_.assign(colours + 1, 0);
  for (int chunk = 0; chunk < chunks; ++chunk) ++colour_start_[colour[chunk] + 1];
  for (int c = 0; c < colours; ++c) colour_start_[c + 1] += colour_start_[c];
  coloured_chunks_.resize(chunks);
  std::vector<int> next(colour_start_.begin(), colour_start_.end() - 1);
  for (int chunk = 0; chunk < chunks; ++chunk) coloured_chunks_[next[colour[chunk]]++] = chunk;
}

void Assembler::assemble(std::span<const double> u, std::span<double> gradient, SparseMatrix* stiffness) const {
  if (stiffness) require_tangent_layout();
  const int folded = linear_ ? (linear_->update(), linear_->folded_count()) : 0;
  if (folded > 0) {
    linear_->multiply(u, gradient);
    if (stiffness) linear_->copy_free(stiffness->values);
  } else {
    std::fill(gradient.begin(), gradient.end(), 0.0);
    if (stiffness) std::fill(stiffness->values.begin(), stiffness->values.end(), 0.0);
  }
  if (folded < model_->cell_count()) assemble_kernels(u, gradient, stiffness);
  nodal_.assemble(u, gradient, stiffness);
  if (!distribution_) return;
  // A divided state reads its own rows only: its ghost rows are partial
  // sums, zeroed; the other rows were never touched.
  if (distribution_->divides_state()) distribution_->zero_ghost_dofs(gradient);
  else distribution_->complete_dofs(gradient);
}

const std::vector<int>& Assembler::changing_rows() const {
  const long folds = linear_ ? (linear_->update(), linear_->changes()) : 0;
  if (folds == changing_seen_folds_) return changing_rows_;
  changing_seen_folds_ = folds;
  ++changing_revision_;
  const Model& model = *model_;
  const int d = model.dim();
  std::vector<char> changing(model.free_dof_count(), 0);
  const auto mark = [&](int node) {
    for (int a = 0; a < d; ++a)
      if (const int row = model.free_index()[node * d + a]; row >= 0) changing[row] = 1;
  };
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    if (linear_ && linear_->folded(cell)) continue;
    for (int node : model.cell_nodes(cell)) mark(node);
  }
  for (int patch = 0; patch < nodal_.patch_count(); ++patch)
    if (nodal_.patch_changes(patch))
      for (int node : nodal_.patch_nodes(patch)) mark(node);
  changing_rows_.clear();
  for (int row = 0; row < model.free_dof_count(); ++row)
    if (changing[row]) changing_rows_.push_back(row);
  return changing_rows_;
}

void Assembler::tangent_product(const SparseMatrix& K, std::span<const double> x, std::span<double> y) const {
  K.multiply(x, y);
  // K holds this rank's rows only: with a divided state y is complete there and zero elsewhere.
  if (distribution_ && !distribution_->divides_state()) distribution_->complete_free(y);
}

void Assembler::assemble_kernels(std::span<const double> u, std::span<double> gradient, SparseMatrix* stiffness) const {
  const Model& model = *model_;
  const int cells = model.cell_count();
  const int active = (distribution_ ? distribution_->assembled_cell_count() : cells) - folded_cell_count();
  update_plan();
  // One parallel region for all colours; small (or mostly folded) meshes
  // stay on one thread, where the barriers between colours would cost more
  // than they save.
  const int colours = colour_count();
#pragma omp parallel if (active >= kParallelCells)
  {
    CellBuffers buffers(stiffness != nullptr);
    BatchBuffers batch_buffers;
    for (int c = 0; c < colours; ++c) {
#pragma omp for schedule(dynamic, 1)
      for (int k = colour_start_[c]; k < colour_start_[c + 1]; ++k) {
        // A chunk's steps are planned from its cells and their laws alone:
        // the order of the sums does not depend on the threads.
        const int chunk = coloured_chunks_[k];
        for (const KernelPlan::Step& step : plan_.steps(chunk)) {
          if (step.batch < 0) assemble_cell(step.cell, u, gradient, stiffness, buffers);
          else run_batch(chunk, plan_.batch(chunk, step.batch), u, gradient, stiffness, batch_buffers);
        }
      }
    }
  }
}

bool Assembler::batches(int cell) const {
  const tm_kernel& kernel = model_->kernel(cell);
  return batched_ && kernel.batch_width > 1 && kernel.batch_width <= KernelPlan::kMaxBatch &&
         !model_->blend_from(cell) && kernel.prony_terms == 0;  // viscous cells are adjusted one by one
}

KernelPlan::Mode Assembler::plan_mode(int cell) const {
  if ((linear_ && linear_->folded(cell)) || (distribution_ && !distribution_->assembles_cell(cell)))
    return KernelPlan::kSkip;
  return batches(cell) ? KernelPlan::kBatched : KernelPlan::kSingle;
}

void Assembler::update_plan() const {
  const Model& model = *model_;
  const PlanKey key{model.law_revision(), model.consts_revision(), batched_, distribution_};
  if (key == plan_key_) return;
  // Laws and blends alone: the plan finds the chunks where they moved.
  // Settings and recomputed constants do not show in the kernels: plan all.
  const bool everything = plan_key_.law_revision < 0 || key.consts_revision != plan_key_.consts_revision ||
                          key.batched != plan_key_.batched || key.distribution != plan_key_.distribution;
  plan_.update(
      model, kChunkCells, [this](int cell) { return plan_mode(cell); }, everything);
  plan_key_ = key;
}

void Assembler::run_batch(int chunk, const KernelPlan::Batch& batch, std::span<const double> u,
                          std::span<double> gradient, SparseMatrix* stiffness, BatchBuffers& buffers) const {
  const tm_kernel& kernel = *batch.kernel;
  const int width = kernel.batch_width, dofs = kernel.dofs, nodes = kernel.nodes;
  const int* node_dofs = plan_.dofs(chunk, batch);
  const double* consts = plan_.consts(chunk, batch);
  buffers.u.resize(static_cast<std::size_t>(dofs) * width);
  buffers.g.resize(static_cast<std::size_t>(dofs) * width);
  with_batch_shape(kernel, [&]<int D, int N>() {
    const auto pack = width == 4 ? pack_lanes<4, D, N> : width == 2 ? pack_lanes<2, D, N> : pack_lanes<0, D, N>;
    pack(node_dofs, nodes, width, u.data(), buffers.u.data());
  });
  if (!stiffness) {
    kernel.gradient_batch(buffers.u.data(), consts, buffers.g.data());
    with_batch_shape(kernel, [&]<int D, int N>() {
      scatter_lanes<D, N>(node_dofs, nodes, width, batch.size, buffers.g.data(), gradient.data());
    });
    return;
  }
  buffers.k.resize(static_cast<std::size_t>(dofs) * dofs * width);
  kernel.gradient_hessian_batch(buffers.u.data(), consts, buffers.g.data(), buffers.k.data());
  const std::size_t dofs2 = static_cast<std::size_t>(dofs) * dofs;
  for (int lane = 0; lane < batch.size; ++lane) {
    double* k = buffers.k.data() + lane * dofs2;
    if (project_hessians_) project_to_positive_semidefinite(k, dofs);
    scatter_cell(batch.cells[lane], buffers.g.data() + static_cast<std::size_t>(lane) * dofs, k, gradient, stiffness);
  }
}

double Assembler::energy(std::span<const double> u) const {
  const Model& model = *model_;
  const int folded = linear_ ? (linear_->update(), linear_->folded_count()) : 0;
  double total = 0.0;
  if (folded > 0) {
    std::vector<double> g(u.size());
    linear_->multiply(u, g);
    if (distribution_) distribution_->keep_own_dofs(g);  // each row counted on one rank
    for (std::size_t d = 0; d < u.size(); ++d) total += 0.5 * u[d] * g[d];
  }
  if (!nodal_.empty()) total += nodal_.energy(u);
  const int cells = model.cell_count();
  if (folded == cells) return distribution_ ? parallel::sum_over_ranks(total) : total;
  const Distribution* shared = distribution_;
  const int chunks = (cells + kChunkCells - 1) / kChunkCells;
  std::vector<double> chunk_energy(chunks, 0.0);
#pragma omp parallel for schedule(dynamic, 1) if (cells - folded >= kParallelCells)
  for (int chunk = 0; chunk < chunks; ++chunk) {
    double local[CellBuffers::kMaxDofs], sum = 0.0;
    for (int cell = chunk * kChunkCells; cell < std::min(cells, (chunk + 1) * kChunkCells); ++cell) {
      if ((linear_ && linear_->folded(cell)) || (shared && !shared->owns_cell(cell))) continue;
      model.gather(cell, u, local);
      const double W = cell_energy(model, cell, local);
      const int viscous = viscous_.index_of(cell);
      sum += viscous < 0 ? W : viscous_.adjust_energy(viscous, local, W);
    }
    chunk_energy[chunk] = sum;
  }
  for (double e : chunk_energy) total += e;
  return distribution_ ? parallel::sum_over_ranks(total) : total;
}

void Assembler::assemble_cell(int cell, std::span<const double> u, std::span<double> gradient, SparseMatrix* stiffness,
                              CellBuffers& buffers) const {
  const Model& model = *model_;
  const tm_kernel& kernel = model.kernel(cell);
  double* local_k = stiffness ? buffers.k.data() : nullptr;
  model.gather(cell, u, buffers.u);
  if (model.blend_from(cell)) {
    blend_cell(model, cell, buffers.u, buffers.g, local_k, buffers.blend_g, buffers.blend_k);
  } else if (stiffness) {
    kernel.gradient_hessian(buffers.u, model.consts(cell), buffers.g, local_k);
  } else {
    kernel.gradient(buffers.u, model.consts(cell), buffers.g);
  }
  if (const int viscous = viscous_.index_of(cell); viscous >= 0)
    viscous_.adjust(viscous, buffers.u, buffers.g, local_k);
  if (stiffness && project_hessians_) project_to_positive_semidefinite(local_k, kernel.dofs);
  scatter_cell(cell, buffers.g, local_k, gradient, stiffness);
}

namespace {

/// values += the node blocks of one cell's Hessian k (nodes*D by nodes*D)
/// at the positions `blocks` (nodes by nodes, Assembler::block_scatter_).
template <int D>
void add_node_blocks(std::span<const int> nodes, const int* blocks, const int* row_length, const double* k,
                     double* values) {
  const int m = static_cast<int>(nodes.size()), n = m * D;
  for (int i = 0; i < m; ++i) {
    const int stride = row_length[nodes[i]];
    for (int j = 0; j < m; ++j) {
      const int base = blocks[i * m + j];
      if (base < 0) continue;
      const double* block = k + static_cast<std::ptrdiff_t>(i) * D * n + j * D;
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) values[base + a * stride + b] += block[a * n + b];
    }
  }
}

}  // namespace

void Assembler::scatter_cell(int cell, const double* g, const double* k, std::span<double> gradient,
                             SparseMatrix* stiffness) const {
  const Model& model = *model_;
  const int d = model.dim();
  const auto cn = model.cell_nodes(cell);
  if (stiffness) {
    double* values = stiffness->values.data();
    if (entry_offsets_[cell + 1] > entry_offsets_[cell]) {
      const int* scatter = entry_scatter_.data() + entry_offsets_[cell];
      const int dofs2 = static_cast<int>(cn.size()) * d * static_cast<int>(cn.size()) * d;
      for (int e = 0; e < dofs2; ++e)
        if (scatter[e] >= 0) values[scatter[e]] += k[e];
    } else {
      const int* blocks = block_scatter_.data() + block_offsets_[cell];
      if (d == 3) add_node_blocks<3>(cn, blocks, row_length_.data(), k, values);
      else if (d == 2) add_node_blocks<2>(cn, blocks, row_length_.data(), k, values);
      else add_node_blocks<1>(cn, blocks, row_length_.data(), k, values);
    }
  }
  for (int j = 0; j < static_cast<int>(cn.size()); ++j)
    for (int a = 0; a < d; ++a) gradient[static_cast<std::size_t>(cn[j]) * d + a] += g[j * d + a];
}

}  // namespace tensormass
