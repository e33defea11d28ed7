// solver.linear.type: petsc: the free-dof system solved by a PETSc KSP
// (default: conjugate gradients preconditioned by smoothed-aggregation
// algebraic multigrid, GAMG, with the rigid-body modes when the free dofs
// are whole nodes). On one process the matrix is a SeqAIJ with the
// assembler's pattern, set up once, and each factorize() copies the values;
// once distribute()d over MPI ranks it is an MPIAIJ of which each rank sets
// its own rows (complete in its partial assembly: Distribution) and the
// solution is gathered to every rank. The preconditioner is rebuilt only
// when lagged solves grow dear (count_solve); options come from
// linear.petsc_options under a prefix of this solver's own.
#include <petscksp.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "parallel/petsc_start.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/parallel/distribution.hpp"
#include "tensormass/parallel/mpi_world.hpp"

namespace tensormass {

namespace {

/// Throws when a PETSc call failed, with PETSc's message (errors are
/// returned, not printed: see initialize()).
void check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw NumericalError(std::string("PETSc: ") + what + " failed: " + (text ? text : "error " + std::to_string(code)) +
                       " (TENSORMASS_PETSC_TRACEBACK=1 prints PETSc's own message)");
}

class PetscSolver final : public LinearSolver {
 public:
  explicit PetscSolver(const LinearSolverSettings& settings) : settings_(settings) {
    parallel::detail::ensure_petsc_started();
    static std::atomic<int> count{0};
    prefix_ = "tensormass" + std::to_string(count++) + "_";
    check(PetscOptionsPrefixPush(nullptr, prefix_.c_str()), "PetscOptionsPrefixPush");
    const PetscErrorCode inserted = PetscOptionsInsertString(nullptr, settings.petsc_options.c_str());
    PetscOptionsPrefixPop(nullptr);
    if (inserted != 0)
      throw InputError("solver.linear.petsc_options '" + settings.petsc_options + "': not PETSc options");
    make_ksp(PETSC_COMM_SELF);
  }
  ~PetscSolver() override {
    // A solver that outlives PETSc (a Python object collected after the
    // interpreter's exit handlers finalised MPI) has nothing left to free.
    PetscBool finalized = PETSC_FALSE;
    PetscFinalized(&finalized);
    if (finalized) return;
    if (ksp_) KSPDestroy(&ksp_);
    destroy_matrix();
  }
  PetscSolver(const PetscSolver&) = delete;
  PetscSolver& operator=(const PetscSolver&) = delete;

  void distribute(const Distribution& distribution) override {
    if (distribution.size() != parallel::world_size())
      throw std::invalid_argument("PETSc solver: a distribution over " + std::to_string(distribution.size()) +
                                  " ranks on " + std::to_string(parallel::world_size()) + " MPI ranks");
    distribution_ = &distribution;
    destroy_matrix();
    KSPDestroy(&ksp_);
    make_ksp(PETSC_COMM_WORLD);
    built_ = false;
  }

  void factorize(const SparseMatrix& A) override {
    if (!matrix_ || rows_ != A.rows || nonzeros_ != A.nonzeros()) create(A);
    if (distribution_) {
      set_own_rows(A);
    } else {
      PetscScalar* values = nullptr;
      check(MatSeqAIJGetArray(matrix_, &values), "MatSeqAIJGetArray");
      std::memcpy(values, A.values.data(), sizeof(double) * A.values.size());
      check(MatSeqAIJRestoreArray(matrix_, &values), "MatSeqAIJRestoreArray");
    }
    check(MatAssemblyBegin(matrix_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
    check(MatAssemblyEnd(matrix_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    // The preconditioner is built afresh only when the policy asks (the
    // first time, or once lagged solves cost more than the cycle's mean);
    // a direct solve (preonly) has no iterations to make up for an old factor.
    use_preconditioner(!built_ || rebuild_next_ || settings_.reuse_iterations == 0 || !krylov_);
  }

  int solve(std::span<const double> b, std::span<double> x, double tolerance) override {
    // CG gets a bounded attempt: it stalls rather than fails where the
    // tangent or the preconditioner is not positive definite.
    const int attempt = cg_ ? std::min(settings_.max_iterations, kCgAttemptIterations) : settings_.max_iterations;
    check(KSPSetTolerances(ksp_, tolerance, 0.0, PETSC_DEFAULT, attempt), "KSPSetTolerances");
    start_.assign(x.begin(), x.end());  // to start again if a solve fails
    KSPConvergedReason reason = run_ksp(b, x);
    if (reason < 0 && !rebuilding_) {
      // The reused preconditioner no longer fits the matrix (its smoothers'
      // eigenvalue bounds, say): build it afresh and solve again.
      use_preconditioner(true);
      std::copy(start_.begin(), start_.end(), x.begin());
      reason = run_ksp(b, x);
    }
    if (reason < 0 && cg_) {
      // CG on an indefinite tangent or preconditioner (a large-deflection
      // static StVK step: CG + GAMG stalled at 1e-4 where GMRES + GAMG
      // took about 20 iterations per solve): GMRES for the rest of the run, as
      // CHOLMOD falls back to LDL^T.
      switch_to_gmres();
      use_preconditioner(true);
      check(KSPSetTolerances(ksp_, tolerance, 0.0, PETSC_DEFAULT, settings_.max_iterations), "KSPSetTolerances");
      std::copy(start_.begin(), start_.end(), x.begin());
      reason = run_ksp(b, x);
    }
    PetscInt iterations = 0;
    KSPGetIterationNumber(ksp_, &iterations);
    if (reason < 0)
      throw NumericalError(std::string("PETSc's linear solve did not converge (") + KSPConvergedReasons[reason] +
                           ") after " + std::to_string(iterations) + " iterations");
    count_solve(static_cast<int>(iterations));
    if (!options_checked_) find_unused_options();
    return static_cast<int>(iterations);
  }

  std::vector<std::string> take_warnings() override { return std::move(warnings_); }

  void set_node_blocks(int dim, std::span<const double> coordinates) override {
    block_size_ = dim;
    coordinates_.assign(coordinates.begin(), coordinates.end());
    destroy_matrix();  // made again with the blocks at the next factorize()
    built_ = false;
  }

  std::string name() const override {
    KSPType ksp_type = nullptr;
    KSPGetType(ksp_, &ksp_type);
    PC pc;
    PCType pc_type = nullptr;
    KSPGetPC(ksp_, &pc);
    PCGetType(pc, &pc_type);
    return std::string("petsc (") + (ksp_type ? ksp_type : "?") + ", " + (pc_type ? pc_type : "?") + ")";
  }

 private:
  /// The Krylov solver on `comm`, CG + GAMG unless the options say otherwise.
  void make_ksp(MPI_Comm comm) {
    const LinearSolverSettings& settings = settings_;
    check(KSPCreate(comm, &ksp_), "KSPCreate");
    check(KSPSetOptionsPrefix(ksp_, prefix_.c_str()), "KSPSetOptionsPrefix");
    check(KSPSetType(ksp_, KSPCG), "KSPSetType");
    // The tolerance is on the true residual |b - A x| / |b|, as for the other solvers.
    check(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
    check(KSPSetTolerances(ksp_, settings.tolerance, 0.0, PETSC_DEFAULT, settings.max_iterations), "KSPSetTolerances");
    PC pc;
    check(KSPGetPC(ksp_, &pc), "KSPGetPC");
    check(PCSetType(pc, PCGAMG), "PCSetType");
    if (KSPSetFromOptions(ksp_) != 0)
      throw InputError("solver.linear.petsc_options '" + settings.petsc_options +
                       "': PETSc refused them (a misspelt -ksp_type or -pc_type?)");
    KSPType type = nullptr;
    check(KSPGetType(ksp_, &type), "KSPGetType");
    cg_ = std::strcmp(type, KSPCG) == 0;
    // Krylov methods start from the caller's x; preonly (a direct solve) takes none.
    krylov_ = std::strcmp(type, KSPPREONLY) != 0;
    check(KSPSetInitialGuessNonzero(ksp_, krylov_ ? PETSC_TRUE : PETSC_FALSE), "KSPSetInitialGuessNonzero");
  }

  /// GMRES from here on, with right preconditioning so that its residual
  /// is the true one (the tolerance means the same as with CG).
  void switch_to_gmres() {
    check(KSPSetType(ksp_, KSPGMRES), "KSPSetType");
    check(KSPSetPCSide(ksp_, PC_RIGHT), "KSPSetPCSide");
    check(KSPGMRESSetRestart(ksp_, 50), "KSPGMRESSetRestart");
    check(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
    cg_ = false;
  }

  /// The matrix with A's pattern (both triangles, sorted columns), and the vectors.
  void create(const SparseMatrix& A) {
    destroy_matrix();
    if (distribution_) return create_distributed(A);
    check(MatCreate(PETSC_COMM_SELF, &matrix_), "MatCreate");
    check(MatSetSizes(matrix_, A.rows, A.rows, A.rows, A.rows), "MatSetSizes");
    check(MatSetType(matrix_, MATSEQAIJ), "MatSetType");
    const bool blocks = block_size_ > 1 && coordinates_.size() == static_cast<std::size_t>(A.rows);
    if (blocks) check(MatSetBlockSize(matrix_, block_size_), "MatSetBlockSize");
    check(MatSeqAIJSetPreallocationCSR(matrix_, A.row_start.data(), A.columns.data(), A.values.data()),
          "MatSeqAIJSetPreallocationCSR");
    check(MatSetOption(matrix_, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
    check(MatSetOption(matrix_, MAT_SYMMETRY_ETERNAL, PETSC_TRUE), "MatSetOption");
    if (blocks) set_rigid_body_modes();
    check(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, A.rows, nullptr, &b_), "VecCreateSeqWithArray");
    check(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, A.rows, nullptr, &x_), "VecCreateSeqWithArray");
    rows_ = A.rows;
    nonzeros_ = A.nonzeros();
  }

  void destroy_matrix() {
    if (matrix_) MatDestroy(&matrix_);
    if (b_) VecDestroy(&b_);
    if (x_) VecDestroy(&x_);
    if (gather_) VecScatterDestroy(&gather_);
    if (x_all_) VecDestroy(&x_all_);
    rows_ = nonzeros_ = -1;
  }

  /// An MPIAIJ with this rank's rows of A's pattern in the global numbering
  /// (columns sorted), the vectors, and the scatter that gathers a solution
  /// to every rank. The pattern is given once, here, and not kept:
  /// set_own_rows finds each entry's place again from A.
  void create_distributed(const SparseMatrix& A) {
    const Distribution& dist = *distribution_;
    const auto& global = dist.global_row();
    const auto& own = dist.owned_free_rows();
    const PetscInt local = static_cast<PetscInt>(own.size());
    {
      std::vector<PetscInt> row_start(1, 0), columns;
      for (int r : own) {
        const std::size_t first = columns.size();
        for (int k = A.row_start[r]; k < A.row_start[r + 1]; ++k) columns.push_back(global[A.columns[k]]);
        std::sort(columns.begin() + static_cast<std::ptrdiff_t>(first), columns.end());
        row_start.push_back(static_cast<PetscInt>(columns.size()));
      }
      check(MatCreate(PETSC_COMM_WORLD, &matrix_), "MatCreate");
      const PetscInt rows = dist.global_row_count();
      check(MatSetSizes(matrix_, local, local, rows, rows), "MatSetSizes");
      check(MatSetType(matrix_, MATMPIAIJ), "MatSetType");
      check(MatMPIAIJSetPreallocationCSR(matrix_, row_start.data(), columns.data(), nullptr),
            "MatMPIAIJSetPreallocationCSR");
    }
    const bool blocks = block_size_ > 1 && coordinates_.size() == static_cast<std::size_t>(A.rows);
    if (blocks) check(MatSetBlockSize(matrix_, block_size_), "MatSetBlockSize");
    check(MatSetOption(matrix_, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
    check(MatSetOption(matrix_, MAT_SYMMETRY_ETERNAL, PETSC_TRUE), "MatSetOption");
    check(MatSetOption(matrix_, MAT_NO_OFF_PROC_ENTRIES, PETSC_TRUE), "MatSetOption");
    if (blocks) set_rigid_body_modes();
    check(MatCreateVecs(matrix_, &x_, &b_), "MatCreateVecs");
    // A divided state takes the solution's own rows only: no gathering.
    if (!dist.divides_state()) check(VecScatterCreateToAll(x_, &gather_, &x_all_), "VecScatterCreateToAll");
    rows_ = A.rows;
    nonzeros_ = A.nonzeros();
  }

  /// Copies this rank's rows of A (complete there) into the MPIAIJ's two
  /// blocks in place. A row's entries in the diagonal block (columns this
  /// rank owns) come in A's order, the global numbering keeping each rank's
  /// order; the off-diagonal block holds the rest sorted by global column.
  void set_own_rows(const SparseMatrix& A) {
    const auto& own = distribution_->owned_free_rows();
    const auto& global = distribution_->global_row();
    const PetscInt first = distribution_->first_global_row(), last = first + static_cast<PetscInt>(own.size());
    Mat diagonal_block, off_block;
    const PetscInt* garray = nullptr;
    check(MatMPIAIJGetSeqAIJ(matrix_, &diagonal_block, &off_block, &garray), "MatMPIAIJGetSeqAIJ");
    const PetscInt *diagonal_start = nullptr, *off_start = nullptr, *unused = nullptr;
    PetscInt rows = 0;
    PetscBool done = PETSC_FALSE;
    check(MatGetRowIJ(diagonal_block, 0, PETSC_FALSE, PETSC_FALSE, &rows, &diagonal_start, &unused, &done),
          "MatGetRowIJ");
    check(MatGetRowIJ(off_block, 0, PETSC_FALSE, PETSC_FALSE, &rows, &off_start, &unused, &done), "MatGetRowIJ");
    PetscScalar *diagonal_values = nullptr, *off_values = nullptr;
    check(MatSeqAIJGetArray(diagonal_block, &diagonal_values), "MatSeqAIJGetArray");
    check(MatSeqAIJGetArray(off_block, &off_values), "MatSeqAIJGetArray");
    std::vector<std::pair<PetscInt, double>> off_row;
    bool fits = true;
    for (std::size_t i = 0; i < own.size() && fits; ++i) {
      const int r = own[i];
      PetscInt d = diagonal_start[i];
      off_row.clear();
      for (int k = A.row_start[r]; k < A.row_start[r + 1]; ++k) {
        const PetscInt column = global[A.columns[k]];
        if (column >= first && column < last) diagonal_values[d++] = A.values[k];
        else off_row.push_back({column, A.values[k]});
      }
      std::sort(off_row.begin(), off_row.end());
      for (std::size_t k = 0; k < off_row.size(); ++k) off_values[off_start[i] + k] = off_row[k].second;
      fits = d == diagonal_start[i + 1] && off_start[i] + static_cast<PetscInt>(off_row.size()) == off_start[i + 1];
    }
    MatSeqAIJRestoreArray(diagonal_block, &diagonal_values);
    MatSeqAIJRestoreArray(off_block, &off_values);
    MatRestoreRowIJ(diagonal_block, 0, PETSC_FALSE, PETSC_FALSE, &rows, &diagonal_start, &unused, &done);
    MatRestoreRowIJ(off_block, 0, PETSC_FALSE, PETSC_FALSE, &rows, &off_start, &unused, &done);
    if (!fits) throw std::logic_error("PETSc solver: a row's entries do not match the matrix's pattern");
  }

  /// The near null space of elasticity (translations and rotations of the
  /// free nodes) for the multigrid's coarse spaces.
  void set_rigid_body_modes() {
    std::vector<double> own_coordinates;
    if (distribution_)
      for (int r : distribution_->owned_free_rows()) own_coordinates.push_back(coordinates_[r]);
    std::vector<double>& points = distribution_ ? own_coordinates : coordinates_;
    Vec coordinates;
    const PetscInt count = static_cast<PetscInt>(points.size());
    check(distribution_
              ? VecCreateMPIWithArray(PETSC_COMM_WORLD, block_size_, count, PETSC_DECIDE, points.data(), &coordinates)
              : VecCreateSeqWithArray(PETSC_COMM_SELF, block_size_, count, points.data(), &coordinates),
          "VecCreateWithArray");
    MatNullSpace modes;
    const PetscErrorCode made = MatNullSpaceCreateRigidBody(coordinates, &modes);
    VecDestroy(&coordinates);
    check(made, "MatNullSpaceCreateRigidBody");
    check(MatSetNearNullSpace(matrix_, modes), "MatSetNearNullSpace");
    MatNullSpaceDestroy(&modes);
  }

  /// The matrix for the next solves, with the preconditioner reused or
  /// rebuilt from its values. A rebuild resets the PC first: a PC reused
  /// once records the matrix's state and would otherwise skip the setup.
  void use_preconditioner(bool rebuild) {
    rebuilding_ = rebuild;
    if (rebuild && built_) {
      PC pc;
      check(KSPGetPC(ksp_, &pc), "KSPGetPC");
      check(PCReset(pc), "PCReset");
    }
    check(KSPSetReusePreconditioner(ksp_, rebuild ? PETSC_FALSE : PETSC_TRUE), "KSPSetReusePreconditioner");
    check(KSPSetOperators(ksp_, matrix_, matrix_), "KSPSetOperators");
    built_ = true;
  }

  /// KSPSolve on b and x in place; its converged (> 0) or diverged (< 0) reason.
  KSPConvergedReason run_ksp(std::span<const double> b, std::span<double> x) {
    if (distribution_) return run_distributed_ksp(b, x);
    check(VecPlaceArray(b_, b.data()), "VecPlaceArray");
    check(VecPlaceArray(x_, x.data()), "VecPlaceArray");
    const PetscErrorCode solved = KSPSolve(ksp_, b_, x_);
    VecResetArray(b_);
    VecResetArray(x_);
    check(solved, "KSPSolve");
    KSPConvergedReason reason;
    check(KSPGetConvergedReason(ksp_, &reason), "KSPGetConvergedReason");
    return reason;
  }

  /// run_ksp over the ranks: each rank gives its own rows of b and x, and
  /// the solution comes back to all (with a divided state: to its own rows).
  KSPConvergedReason run_distributed_ksp(std::span<const double> b, std::span<double> x) {
    const auto& own = distribution_->owned_free_rows();
    PetscScalar *b_local = nullptr, *x_local = nullptr;
    check(VecGetArray(b_, &b_local), "VecGetArray");
    check(VecGetArray(x_, &x_local), "VecGetArray");
    for (std::size_t i = 0; i < own.size(); ++i) b_local[i] = b[own[i]], x_local[i] = x[own[i]];
    VecRestoreArray(b_, &b_local);
    VecRestoreArray(x_, &x_local);
    check(KSPSolve(ksp_, b_, x_), "KSPSolve");
    KSPConvergedReason reason;
    check(KSPGetConvergedReason(ksp_, &reason), "KSPGetConvergedReason");
    if (distribution_->divides_state()) {
      const PetscScalar* mine = nullptr;
      check(VecGetArrayRead(x_, &mine), "VecGetArrayRead");
      for (std::size_t i = 0; i < own.size(); ++i) x[own[i]] = mine[i];
      VecRestoreArrayRead(x_, &mine);
      return reason;
    }
    check(VecScatterBegin(gather_, x_, x_all_, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
    check(VecScatterEnd(gather_, x_, x_all_, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
    const PetscScalar* all = nullptr;
    check(VecGetArrayRead(x_all_, &all), "VecGetArrayRead");
    const auto& global = distribution_->global_row();
    for (std::size_t r = 0; r < x.size(); ++r) x[r] = all[global[r]];
    VecRestoreArrayRead(x_all_, &all);
    return reason;
  }

  /// After the first solve (the preconditioner's levels read theirs at
  /// its setup): the scene's options that PETSc never looked up, misspelt
  /// or meant for a method not in use. PETSc itself says nothing of them.
  void find_unused_options() {
    options_checked_ = true;
    PetscInt count = 0;
    char **names = nullptr, **values = nullptr;
    if (PetscOptionsLeftGet(nullptr, &count, &names, &values) != 0) return;
    std::string unused;
    for (PetscInt i = 0; i < count; ++i)
      if (std::strncmp(names[i], prefix_.c_str(), prefix_.size()) == 0)
        unused += std::string(unused.empty() ? "" : ", ") + "-" + (names[i] + prefix_.size());
    PetscOptionsLeftRestore(nullptr, &count, &names, &values);
    if (!unused.empty())
      warnings_.push_back("solver.linear.petsc_options: PETSc did not use " + unused +
                          " (misspelt, or for a method not in use; options outside the linear solve, such as "
                          "-log_view, go in the PETSC_OPTIONS environment variable)");
  }

  /// The reuse policy in iterations (counts, not clocks: runs repeat
  /// bitwise): a cycle starts when the preconditioner is built (costing
  /// kSetupCost iterations) and the next build is asked for as soon as a
  /// lagged solve takes more iterations than the cycle's mean cost per solve.
  void count_solve(int iterations) {
    if (rebuilding_) {
      cycle_cost_ = kSetupCost, cycle_solves_ = 0, rebuilding_ = false;
      rebuild_next_ = false;
    } else {
      rebuild_next_ = iterations > (cycle_cost_ + iterations) / (cycle_solves_ + 1);
    }
    cycle_cost_ += iterations;
    ++cycle_solves_;
  }
  /// A GAMG setup in CG iterations: 100 to 110 ms against 1.5 ms per
  /// iteration on the 24,000-tet indentation block (13k dofs, AMD EPYC).
  static constexpr double kSetupCost = 70.0;
  /// CG's iterations before GMRES takes over (GAMG usually needs 10 to 100).
  static constexpr int kCgAttemptIterations = 200;
  bool cg_ = false;     ///< the Krylov method is CG (which falls back to GMRES)
  bool krylov_ = true;  ///< false for preonly: a direct solve with the preconditioner's factor

  bool built_ = false, rebuilding_ = false, rebuild_next_ = false;
  bool options_checked_ = false;
  std::vector<std::string> warnings_;
  double cycle_cost_ = 0.0;
  int cycle_solves_ = 0;
  LinearSolverSettings settings_;
  std::vector<double> coordinates_;
  std::vector<double> start_;  ///< the initial guess of a lagged solve
  int block_size_ = 1;
  std::string prefix_;
  KSP ksp_ = nullptr;
  Mat matrix_ = nullptr;
  Vec b_ = nullptr, x_ = nullptr;
  int rows_ = -1, nonzeros_ = -1;
  // Distributed (null on one process): this rank's rows in the global numbering.
  const Distribution* distribution_ = nullptr;
  VecScatter gather_ = nullptr;  ///< x to x_all_ on every rank
  Vec x_all_ = nullptr;
};

}  // namespace

bool petsc_available() { return true; }

std::unique_ptr<LinearSolver> make_petsc_solver(const LinearSolverSettings& settings) {
  return std::make_unique<PetscSolver>(settings);
}

}  // namespace tensormass
