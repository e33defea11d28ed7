#include "tensormass/assembly/kernel_plan.hpp"

#include <algorithm>

namespace tensormass {

void KernelPlan::update(const Model& model, int chunk_cells, const std::function<Mode(int)>& mode, bool everything) {
  const int cells = model.cell_count();
  if (chunk_cells != chunk_cells_ || planned_kernel_.size() != static_cast<std::size_t>(cells)) {
    chunk_cells_ = chunk_cells;
    chunks_.assign((cells + chunk_cells - 1) / chunk_cells, Chunk{});
    planned_kernel_.assign(cells, nullptr);
    planned_blend_.assign(cells, nullptr);
    planned_mode_.assign(cells, kSkip);
    everything = true;
  }
  for (int chunk = 0; chunk < static_cast<int>(chunks_.size()); ++chunk) {
    const int first = chunk * chunk_cells, last = std::min(cells, first + chunk_cells);
    // A mode follows from the cell's kernel and blend (and the settings):
    // chunks where neither moved keep their plan without asking mode().
    bool moved = everything;
    for (int cell = first; cell < last && !moved; ++cell)
      moved = &model.kernel(cell) != planned_kernel_[cell] || model.blend_from(cell) != planned_blend_[cell];
    if (!moved) continue;
    bool changed = everything;
    for (int cell = first; cell < last; ++cell) {
      const Mode now = mode(cell);
      changed = changed || now != planned_mode_[cell] || &model.kernel(cell) != planned_kernel_[cell];
      planned_mode_[cell] = now;
      planned_kernel_[cell] = &model.kernel(cell);
      planned_blend_[cell] = model.blend_from(cell);
    }
    if (!changed) continue;
    plan_chunk(model, chunk, first, last);
    ++replanned_;
  }
}

void KernelPlan::plan_chunk(const Model& model, int index, int first, int last) {
  Chunk& chunk = chunks_[index];
  chunk.steps.clear();
  chunk.batches.clear();
  chunk.dofs.clear();
  chunk.consts.clear();
  struct Waiting {
    const tm_kernel* kernel;
    int cells[kMaxBatch];
    int size;
  };
  Waiting waiting[kWaitingBatches];
  int used = 0;
  const auto run = [&](Waiting& batch) {
    if (batch.size > 0) add_batch(model, chunk, *batch.kernel, {batch.cells, static_cast<std::size_t>(batch.size)});
    batch.size = 0;
  };
  const auto run_all = [&] {
    for (int s = 0; s < used; ++s) run(waiting[s]);
    used = 0;
  };
  for (int cell = first; cell < last; ++cell) {
    if (planned_mode_[cell] == kSkip) continue;
    if (planned_mode_[cell] == kSingle) {
      chunk.steps.push_back({cell, -1});
      continue;
    }
    const tm_kernel* kernel = planned_kernel_[cell];
    Waiting* batch = nullptr;
    for (int s = 0; s < used && !batch; ++s)
      if (waiting[s].kernel == kernel) batch = &waiting[s];
    if (!batch) {
      if (used == kWaitingBatches) run_all();
      batch = &waiting[used++];
      batch->kernel = kernel;
      batch->size = 0;
    }
    if (batch->size == kernel->batch_width) run(*batch);
    batch->cells[batch->size++] = cell;
  }
  run_all();
}

void KernelPlan::add_batch(const Model& model, Chunk& chunk, const tm_kernel& kernel, std::span<const int> cells) {
  const int width = kernel.batch_width, used = static_cast<int>(cells.size());
  Batch batch;
  batch.kernel = &kernel;
  batch.size = used;
  std::copy(cells.begin(), cells.end(), batch.cells);
  batch.dofs_offset = chunk.dofs.size();
  batch.consts_offset = chunk.consts.size();
  chunk.dofs.resize(batch.dofs_offset + static_cast<std::size_t>(kernel.nodes) * width);
  chunk.consts.resize(batch.consts_offset + static_cast<std::size_t>(kernel.consts) * width);
  int* dofs = chunk.dofs.data() + batch.dofs_offset;
  double* consts = chunk.consts.data() + batch.consts_offset;
  for (int lane = 0; lane < width; ++lane) {
    const int cell = cells[lane < used ? lane : 0];  // lanes past the size repeat the first cell
    const int* nodes = model.cell_nodes(cell).data();
    const double* cell_consts = model.consts(cell);
    for (int j = 0; j < kernel.nodes; ++j) dofs[j * width + lane] = nodes[j] * kernel.dim;
    for (int i = 0; i < kernel.consts; ++i) consts[i * width + lane] = cell_consts[i];
  }
  chunk.steps.push_back({cells[0], static_cast<int>(chunk.batches.size())});
  chunk.batches.push_back(batch);
}

}  // namespace tensormass
