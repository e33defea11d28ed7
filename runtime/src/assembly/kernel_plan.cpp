#include "tensormass/assembly/kernel_plan.hpp"

#include <algorithm>

namespace tensormass {

void KernelPlan::update(const Model& model, int chunk_cells, const std::function<Mode(int)>& mode) {
  const int cells = model.cell_count();
  if (chunk_cells != chunk_cells_ || planned_kernel_.size() != static_cast<std::size_t>(cells)) {
    chunk_cells_ = chunk_cells;
    chunks_.assign((cells + chunk_cells - 1) / chunk_cells, Chunk{});
    planned_kernel_.assign(cells, nullptr);
    planned_mode_.assign(cells, 0xff);  // no mode: every chunk is planned
  }
  for (int chunk = 0; chunk < static_cast<int>(chunks_.size()); ++chunk) {
    const int first = chunk * chunk_cells, last = std::min(cells, first + chunk_cells);
    bool changed = false;
    for (int cell = first; cell < last; ++cell) {
      const Mode now = mode(cell);
      const tm_kernel* kernel = now == kSkip ? nullptr : &model.kernel(cell);
      if (now == planned_mode_[cell] && kernel == planned_kernel_[cell]) continue;
      planned_mode_[cell] = now;
      planned_kernel_[cell] = kernel;
      changed = true;
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
  const auto lane_cell = [&](int lane) { return cells[lane < used ? lane : 0]; };
  for (int j = 0; j < kernel.nodes; ++j)
    for (int lane = 0; lane < width; ++lane) chunk.dofs.push_back(model.cell_nodes(lane_cell(lane))[j] * kernel.dim);
  for (int i = 0; i < kernel.consts; ++i)
    for (int lane = 0; lane < width; ++lane) chunk.consts.push_back(model.consts(lane_cell(lane))[i]);
  chunk.steps.push_back({cells[0], static_cast<int>(chunk.batches.size())});
  chunk.batches.push_back(batch);
}

}  // namespace tensormass
