// solver.linear.type: petsc: the free-dof system solved by a PETSc KSP
// (default: conjugate gradients preconditioned by smoothed-aggregation
// algebraic multigrid, GAMG, with the rigid-body modes when the free dofs
// are whole nodes), on one process. The matrix is a SeqAIJ with the
// assembler's pattern, set up once; each factorize() copies the values; the
// preconditioner is rebuilt only when lagged solves grow dear (count_solve);
// options come from linear.petsc_options under a prefix of this solver's own.
#include <petscksp.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#include "tensormass/common/errors.hpp"
#include "tensormass/solvers/linear_solver.hpp"

namespace tensormass {

namespace {

/// Throws when a PETSc call failed, with PETSc's message (errors are
/// returned, not printed: see initialize()).
void check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw NumericalError(std::string("PETSc: ") + what + " failed: " + (text ? text : "error " + std::to_string(code)));
}

/// PETSc (and MPI, as a singleton process) started once per process, on
/// first use; finalised at exit by PETSc's own atexit handling of MPI.
void initialize() {
  static std::once_flag once;
  std::call_once(once, [] {
    PetscBool started = PETSC_FALSE;
    PetscInitialized(&started);
    if (!started) check(PetscInitializeNoArguments(), "PetscInitialize");
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  });
}

class PetscSolver final : public LinearSolver {
 public:
  explicit PetscSolver(const LinearSolverSettings& settings) : settings_(settings) {
    initialize();
    static std::atomic<int> count{0};
    prefix_ = "tensormass" + std::to_string(count++) + "_";
    check(PetscOptionsPrefixPush(nullptr, prefix_.c_str()), "PetscOptionsPrefixPush");
    const PetscErrorCode inserted = PetscOptionsInsertString(nullptr, settings.petsc_options.c_str());
    PetscOptionsPrefixPop(nullptr);
    if (inserted != 0)
      throw InputError("solver.linear.petsc_options '" + settings.petsc_options + "': not PETSc options");
    check(KSPCreate(PETSC_COMM_SELF, &ksp_), "KSPCreate");
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
    check(KSPSetInitialGuessNonzero(ksp_, PETSC_TRUE), "KSPSetInitialGuessNonzero");
  }
  ~PetscSolver() override {
    if (ksp_) KSPDestroy(&ksp_);
    if (matrix_) MatDestroy(&matrix_);
    if (b_) VecDestroy(&b_);
    if (x_) VecDestroy(&x_);
  }
  PetscSolver(const PetscSolver&) = delete;
  PetscSolver& operator=(const PetscSolver&) = delete;

  void factorize(const SparseMatrix& A) override {
    if (!matrix_ || rows_ != A.rows || nonzeros_ != A.nonzeros()) create(A);
    PetscScalar* values = nullptr;
    check(MatSeqAIJGetArray(matrix_, &values), "MatSeqAIJGetArray");
    std::memcpy(values, A.values.data(), sizeof(double) * A.values.size());
    check(MatSeqAIJRestoreArray(matrix_, &values), "MatSeqAIJRestoreArray");
    check(MatAssemblyBegin(matrix_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
    check(MatAssemblyEnd(matrix_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    // The preconditioner is built afresh only when the policy asks (the
    // first time, or once lagged solves cost more than the cycle's mean).
    use_preconditioner(!built_ || rebuild_next_ || settings_.reuse_iterations == 0);
  }

  int solve(std::span<const double> b, std::span<double> x, double tolerance) override {
    check(KSPSetTolerances(ksp_, tolerance, 0.0, PETSC_DEFAULT, settings_.max_iterations), "KSPSetTolerances");
    if (!rebuilding_) start_.assign(x.begin(), x.end());  // to start again if the lagged solve fails
    KSPConvergedReason reason = run_ksp(b, x);
    if (reason < 0 && !rebuilding_) {
      // The reused preconditioner no longer fits the matrix (its smoothers'
      // eigenvalue bounds, say): build it afresh and solve again.
      use_preconditioner(true);
      std::copy(start_.begin(), start_.end(), x.begin());
      reason = run_ksp(b, x);
    }
    PetscInt iterations = 0;
    KSPGetIterationNumber(ksp_, &iterations);
    if (reason < 0)
      throw NumericalError(std::string("PETSc's linear solve did not converge (") + KSPConvergedReasons[reason] +
                           ") after " + std::to_string(iterations) + " iterations");
    count_solve(static_cast<int>(iterations));
    return static_cast<int>(iterations);
  }

  void set_node_blocks(int dim, std::span<const double> coordinates) override {
    block_size_ = dim;
    coordinates_.assign(coordinates.begin(), coordinates.end());
    if (matrix_) MatDestroy(&matrix_);  // made again with the blocks at the next factorize()
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
  /// The matrix with A's pattern (both triangles, sorted columns), and the vectors.
  void create(const SparseMatrix& A) {
    if (matrix_) MatDestroy(&matrix_);
    if (b_) VecDestroy(&b_);
    if (x_) VecDestroy(&x_);
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

  /// The near null space of elasticity (translations and rotations of the
  /// free nodes) for the multigrid's coarse spaces.
  void set_rigid_body_modes() {
    Vec coordinates;
    check(VecCreateSeqWithArray(PETSC_COMM_SELF, block_size_, static_cast<PetscInt>(coordinates_.size()),
                                coordinates_.data(), &coordinates),
          "VecCreateSeqWithArray");
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

  bool built_ = false, rebuilding_ = false, rebuild_next_ = false;
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
};

}  // namespace

bool petsc_available() { return true; }

std::unique_ptr<LinearSolver> make_petsc_solver(const LinearSolverSettings& settings) {
  return std::make_unique<PetscSolver>(settings);
}

}  // namespace tensormass
