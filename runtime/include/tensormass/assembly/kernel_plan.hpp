/// \file kernel_plan.hpp
/// The order in which Assembler runs the kernels of a mesh's cells, chunk by
/// chunk: single cells, and batches of up to kMaxBatch cells of one kernel
/// (its batched entry points, SIMD across the cells). Planned once per set
/// of laws instead of at every assembly: a planned batch keeps its lanes'
/// node dofs and its constants packed lane by lane (kernel_abi.h's batch
/// layout), so running it copies the displacements only. An explicit step
/// spent twice as long forming and packing batches as in the kernels. The
/// packed constants are a second copy of the batched cells' (the `whole`
/// split's: 15 doubles per tet4 cell, 120 MB at a million non-linear tets).
///
/// The plan follows the cells' laws: update() compares each cell's kernel
/// and mode with the planned ones and plans again only the chunks where one
/// changed. The order of the additions (cells in chunk order, a kernel's
/// batch run when it is full, every waiting batch at the end of the chunk)
/// depends on the cells and their laws only, so results do not depend on
/// the number of threads.
#ifndef TENSORMASS_ASSEMBLY_KERNEL_PLAN_HPP
#define TENSORMASS_ASSEMBLY_KERNEL_PLAN_HPP

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "tensormass/model/model.hpp"

namespace tensormass {

class KernelPlan {
 public:
  /// How a cell is assembled.
  enum Mode : unsigned char {
    kSkip = 0,     ///< not here (folded into the linear part, or another rank's)
    kSingle = 1,   ///< its per-element kernel
    kBatched = 2,  ///< with cells of the same kernel, through the batched entry points
  };
  static constexpr int kMaxBatch = 8;  ///< the widest tm_kernel::batch_width
  /// Batches of distinct kernels waiting at once in a chunk: cells of two or
  /// three laws interleaved (an adaptive run's ladder) still fill theirs.
  static constexpr int kWaitingBatches = 4;

  /// Up to batch_width cells of one kernel, run together.
  struct Batch {
    const tm_kernel* kernel = nullptr;
    int size = 0;  ///< cells in use; lanes past it repeat the first cell
    int cells[kMaxBatch] = {};
    std::size_t dofs_offset = 0;    ///< into the chunk's dofs: nodes by batch_width, each node's first dof
    std::size_t consts_offset = 0;  ///< into the chunk's consts: consts by batch_width (lane fastest)
  };
  /// One step of a chunk: assemble `cell` alone (batch < 0) or run batch `batch`.
  struct Step {
    int cell;
    int batch;
  };

  /// Brings the plan up to date for chunks of `chunk_cells` consecutive
  /// cells (the last one shorter), mode(cell) saying how each cell is
  /// assembled now, a function of its kernel and blend (Model::blend_from):
  /// mode() is asked only in chunks where a kernel or a blend moved since
  /// the last update, and those where a kernel or a mode changed are
  /// planned again. `everything` (and the first update) asks every mode and
  /// plans every chunk again: for changes the kernels do not show (the
  /// settings behind the modes, recomputed constants).
  void update(const Model& model, int chunk_cells, const std::function<Mode(int)>& mode, bool everything = false);

  std::span<const Step> steps(int chunk) const { return chunks_[chunk].steps; }
  const Batch& batch(int chunk, int index) const { return chunks_[chunk].batches[index]; }
  /// Batch b's node dofs: dofs[j * width + lane] = D * (node j of the lane's cell).
  const int* dofs(int chunk, const Batch& b) const { return chunks_[chunk].dofs.data() + b.dofs_offset; }
  /// Batch b's constants, lane by lane: consts[i * width + lane].
  const double* consts(int chunk, const Batch& b) const { return chunks_[chunk].consts.data() + b.consts_offset; }
  /// Chunks planned again by updates so far (every chunk counts once for the first).
  long replanned_chunks() const { return replanned_; }

 private:
  struct Chunk {
    std::vector<Step> steps;
    std::vector<Batch> batches;
    std::vector<int> dofs;
    std::vector<double> consts;
  };
  void plan_chunk(const Model& model, int chunk, int first, int last);
  /// Appends a batch of `cells` (all of one kernel) to the chunk, packing its lanes.
  void add_batch(const Model& model, Chunk& chunk, const tm_kernel& kernel, std::span<const int> cells);

  int chunk_cells_ = 0;
  std::vector<Chunk> chunks_;
  std::vector<const tm_kernel*> planned_kernel_;  ///< per cell, its kernel when planned
  std::vector<const tm_kernel*> planned_blend_;   ///< per cell, Model::blend_from when planned
  std::vector<unsigned char> planned_mode_;       ///< per cell, as planned
  long replanned_ = 0;
};

}  // namespace tensormass

#endif
