/// \file assembler.hpp
/// Assembly of the internal forces g(u) = dW/du and the tangent stiffness
/// K = dg/du over the free dofs. The sparsity pattern and an
/// element-to-matrix scatter map are built once; chunks of consecutive
/// cells are coloured so that no two chunks of a colour share a node, each
/// colour's chunks are assembled in parallel with plain stores (each chunk
/// in cell order), and colours run in a fixed order: results do not depend
/// on the number of threads.
///
/// Cells under a linear law are not visited per step: they are folded into
/// a constant matrix (LinearPart) whose product with u gives their forces
/// and whose copy starts the tangent, so a step costs kernels only for the
/// non-linear cells. The folded set follows the model's law switches at the
/// next assemble().
///
/// Over MPI ranks (distribute()), each rank runs the kernels of the cells
/// touching its nodes only: its rows are complete, the gradient is completed
/// over the ranks, and products with the tangent go through tangent_product.
///
/// Cells of the anp split add their nodal part (nodal_pressure.hpp) after
/// the kernels; its patches widen the pattern to two rings of neighbours.
/// Cells of a viscoelastic law turn their kernel's force and tangent into
/// the current step's (viscous_part.hpp) before they are scattered.
#ifndef TENSORMASS_ASSEMBLER_HPP
#define TENSORMASS_ASSEMBLER_HPP

#include <memory>
#include <span>
#include <vector>

#include "tensormass/assembly/kernel_plan.hpp"
#include "tensormass/assembly/linear_part.hpp"
#include "tensormass/assembly/nodal_pressure.hpp"
#include "tensormass/assembly/node_graph.hpp"
#include "tensormass/assembly/sparse_matrix.hpp"
#include "tensormass/assembly/viscous_part.hpp"
#include "tensormass/model/model.hpp"
#include "tensormass/parallel/distribution.hpp"

namespace tensormass {

class Assembler {
 public:
  /// fold_linear_cells = false runs every cell's kernel at every assembly
  /// (the reference the folded assembly is tested and benchmarked against).
  /// `distribution`: as distribute(distribution), from the start, so that
  /// the whole mesh's pattern is never built on a rank (nullptr: one process).
  explicit Assembler(const Model& model, bool fold_linear_cells = true, const Distribution* distribution = nullptr);
  explicit Assembler(Model&&, bool = true, const Distribution* = nullptr) = delete;  ///< keeps a reference to the model

  /// A new matrix with the pattern of K (free dofs by free dofs) and zero
  /// values. The assembler keeps the structure only: its callers own the
  /// values (a tangent's worth of memory each). The first call builds the
  /// structure: not re-entrant, like assemble().
  SparseMatrix pattern() const;
  /// gradient (dof_count) = g(u); when `stiffness` is non-null it gets K(u)
  /// restricted to the free dofs (its pattern must be pattern()). Not
  /// re-entrant: it brings the folded linear part up to date first.
  void assemble(std::span<const double> u, std::span<double> gradient, SparseMatrix* stiffness) const;
  /// The strain energy W(u) (u: dof_count) whose gradient assemble() gives:
  /// the folded part 1/2 u.K_L u, the other cells' kernels (blending cells
  /// w W_new + (1 - w) W_old), summed per chunk in a fixed order (the same
  /// value on any thread count). Not re-entrant, like assemble().
  double energy(std::span<const double> u) const;
  /// When on, each kernel cell's Hessian is projected to positive
  /// semi-definite before it is scattered (project_to_positive_semidefinite):
  /// the scene key solver.project_hessian. Folded (linear) cells are
  /// positive semi-definite already. Off by default.
  void set_hessian_projection(bool on) { project_hessians_ = on; }
  bool hessian_projection() const { return project_hessians_; }
  int colour_count() const { return static_cast<int>(colour_start_.size()) - 1; }
  /// Cells folded into the constant linear part (0 when folding is off).
  int folded_cell_count() const { return linear_ ? linear_->folded_count() : 0; }
  /// Cells folded or unfolded so far (law switches in or out of a linear law).
  long folding_changes() const { return linear_ ? linear_->changes() : 0; }
  /// The folded linear part (nullptr when folding is off), for checkpoints.
  LinearPart* linear_part() const { return linear_.get(); }
  /// Shares the work among MPI ranks (nullptr: every cell here, the
  /// default). assemble() then runs the kernels of the cells touching this
  /// rank's nodes and completes the gradient over the ranks (with a divided
  /// state, Distribution::divides_state(): u is read on this part's nodes,
  /// and the gradient is this rank's rows, zero elsewhere); the stiffness
  /// has this rank's rows complete and the others partial; energy() adds
  /// each cell on its owner's rank and sums over the ranks. The
  /// distribution must outlive the assembler.
  /// The pattern then holds this rank's rows only (the other rows are
  /// empty: K's memory is divided among the ranks), and pattern() changes:
  /// take copies of it after this call.
  void distribute(const Distribution* distribution);
  const Distribution* distribution() const { return distribution_; }
  const Model& model() const { return *model_; }
  /// The free dofs (sorted) of the nodes of the cells that run kernels (not
  /// folded): the only rows and columns of K that change between
  /// assemblies while no law switches. Brought up to date with the folded
  /// set; changing_rows_revision() changes when the set does.
  const std::vector<int>& changing_rows() const;
  long changing_rows_revision() const { return changing_revision_; }
  /// y = K x over the free dofs for a stiffness from assemble(), complete on
  /// every rank (with a divided state: this rank's rows, zero elsewhere).
  void tangent_product(const SparseMatrix& K, std::span<const double> x, std::span<double> y) const;
  /// When on (the default), runs of consecutive cells with the same kernel
  /// go through its batched entry points (tm_kernel::batch_width cells per
  /// call, SIMD across the cells); off, every cell calls the per-element
  /// kernel. Results agree to round-off; either way they do not depend on
  /// the thread count. Blending cells always run per element.
  void set_batched(bool on) { batched_ = on; }
  bool batched() const { return batched_; }
  /// The viscous part of the model's viscoelastic cells (empty() without any).
  const ViscousPart& viscous_part() const { return viscous_; }
  /// Sets up the time step of length dt from the viscous history at its
  /// start (State::viscous_history; ViscousPart::begin_step): what
  /// assemble() and energy() give until the next call. Not re-entrant.
  void begin_viscous_step(std::span<const double> history, double dt) const { viscous_.begin_step(history, dt); }
  /// Ends the step at u: the viscous history is updated to it (ViscousPart::commit).
  void commit_viscous_step(std::span<const double> u, std::vector<double>& history) const {
    viscous_.commit(u, history);
  }
  /// The plan of the kernel cells as of the last assemble() (kernel_plan.hpp).
  const KernelPlan& kernel_plan() const { return plan_; }
  /// When on (the default), cell Hessians are added into the tangent by
  /// node blocks (one index per pair of nodes); off, by one index per
  /// Hessian entry (the earlier map, kept for the benchmark). The same
  /// additions in the same order: identical results. Rebuilds the map.
  void set_scatter_by_blocks(bool on);
  bool scatter_by_blocks() const { return scatter_by_blocks_; }
  /// Bytes the scatter maps take (built if they were not).
  std::size_t scatter_map_bytes() const;

 private:
  /// Per-thread scratch space for one cell.
  struct CellBuffers {
    explicit CellBuffers(bool with_stiffness) : k(with_stiffness ? kMaxDofs * kMaxDofs : 0) {}
    static constexpr int kMaxDofs = kMaxCellDofs;
    double u[kMaxDofs], g[kMaxDofs], blend_g[kMaxDofs];
    std::vector<double> k, blend_k;
  };
  /// Per-thread scratch space for one batch (kernel_abi.h layouts).
  struct BatchBuffers {
    std::vector<double> u, g, k;
  };
  void assemble_cell(int cell, std::span<const double> u, std::span<double> gradient, SparseMatrix* stiffness,
                     CellBuffers& buffers) const;
  /// True when the cell runs through its kernel's batched entry points.
  bool batches(int cell) const;
  /// How the plan assembles a cell now (folded and other ranks' cells are skipped).
  KernelPlan::Mode plan_mode(int cell) const;
  /// Brings plan_ up to date when the laws, the folded set or the settings changed.
  void update_plan() const;
  /// Runs one planned batch of `chunk` and scatters its cells in lane order.
  void run_batch(int chunk, const KernelPlan::Batch& batch, std::span<const double> u, std::span<double> gradient,
                 SparseMatrix* stiffness, BatchBuffers& buffers) const;
  /// Adds one cell's gradient g (dofs) and Hessian k (dofs by dofs, or null) into the totals.
  void scatter_cell(int cell, const double* g, const double* k, std::span<double> gradient,
                    SparseMatrix* stiffness) const;
  /// Builds the pattern and the scatter maps at the first need of a
  /// tangent (pattern(), assemble() with a stiffness): an explicit run
  /// never holds them.
  void require_tangent_layout() const;
  void build_pattern() const;
  /// Whether K keeps the rows of `node`: all of them on one process, this rank's own under distribute().
  bool keeps_rows_of(int node) const;
  /// Fills the scatter maps above for the pattern in pattern_.
  void build_scatter_map() const;
  void build_colours();
  /// Throws InputError when the model has anp cells (not distributed yet).
  void refuse_nodal_pressure_over_ranks() const;
  void assemble_kernels(std::span<const double> u, std::span<double> gradient, SparseMatrix* stiffness) const;

  const Model* model_;
  NodalPressure nodal_;  ///< the anp cells' bulk part at the nodes (empty without anp cells)
  /// The viscoelastic cells' history terms; the step it is set up for changes between assemblies.
  mutable ViscousPart viscous_;
  NodeGraph graph_;
  /// The tangent's layout below is built (require_tangent_layout).
  mutable bool tangent_layout_ = false;
  mutable SparseMatrix pattern_;        ///< rows, columns, diagonal and node runs; values empty
  std::unique_ptr<LinearPart> linear_;  ///< null when folding is off; updated by assemble()
  /// The scatter map by node blocks: per cell, node pairs (i, j) (nodes by
  /// nodes) -> the position in values of (i's first free row, j's first
  /// free column), or -1 when i or j has no free dof. Entry (i a, j b) is
  /// at that position + a row_length_[i] + b: a node whose dofs are all
  /// free has d rows of the same columns. 9x fewer indices than one per
  /// Hessian entry in 3D (64 bytes per tet4 instead of 576).
  mutable std::vector<std::size_t> block_offsets_;  ///< cell_count+1
  mutable std::vector<int> block_scatter_;
  mutable std::vector<int> row_length_;  ///< per node: the length of its rows (nodes with every dof free)
  /// Cells with a partly fixed node (some of its dofs free, not all) keep
  /// one index per Hessian entry (dofs by dofs, -1: a fixed row or column).
  mutable std::vector<std::size_t> entry_offsets_;  ///< cell_count+1 (empty range: scattered by blocks)
  mutable std::vector<int> entry_scatter_;
  std::vector<int> colour_start_;     ///< colours+1, into coloured_chunks_
  std::vector<int> coloured_chunks_;  ///< chunk c holds cells [c*S, (c+1)*S)
  bool project_hessians_ = false;
  bool batched_ = true;
  bool scatter_by_blocks_ = true;
  const Distribution* distribution_ = nullptr;
  /// The order of the kernel cells and their packed batches, planned for
  /// the laws (the folded set follows them), constants and settings of plan_key_.
  mutable KernelPlan plan_;
  struct PlanKey {
    long law_revision = -1, consts_revision = -1;
    bool batched = false;
    const Distribution* distribution = nullptr;
    bool operator==(const PlanKey&) const = default;
  };
  mutable PlanKey plan_key_;
  mutable std::vector<int> changing_rows_;
  mutable long changing_revision_ = 0, changing_seen_folds_ = -1;
};

}  // namespace tensormass

#endif
