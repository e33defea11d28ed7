// Sparse Cholesky through the CHOLMOD C API (SuiteSparse), with the
// previous factor reused as a CG preconditioner while that is cheaper than
// a new one (a Newton or implicit step's tangent drifts slowly): see
// FactorReusePolicy.
#include <cholmod.h>
#include <dlfcn.h>
#include <omp.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "solvers/factor_reuse_policy.hpp"
#include "solvers/preconditioned_cg.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/solvers/linear_solver.hpp"

namespace tensormass {

namespace {

/// A's lower triangle as CHOLMOD reads it. A stores both triangles; as
/// compressed columns it is the same (symmetric) matrix, and stype = -1
/// makes CHOLMOD ignore the upper part.
cholmod_sparse view_of(const SparseMatrix& A) {
  cholmod_sparse view{};
  view.nrow = view.ncol = static_cast<std::size_t>(A.rows);
  view.nzmax = A.values.size();
  view.p = const_cast<int*>(A.row_start.data());
  view.i = const_cast<int*>(A.columns.data());
  view.x = const_cast<double*>(A.values.data());
  view.stype = -1;
  view.itype = CHOLMOD_INT;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 1;
  view.packed = 1;
  return view;
}

/// Runs CHOLMOD's BLAS on one thread for its lifetime. Debian's OpenBLAS
/// (openmp variant) takes its thread count from omp_get_max_threads() at
/// every call, and its many small parallel calls on a supernodal factor
/// cost more than they save: a 9,720-dof factorisation took 816 ms on 2
/// threads against 122 ms on one, and a 100k-tet one 6.6 s against 2.0 s
/// (AMD EPYC, 2 cores). The pthreads variant has its own count, set too.
class SerialBlas {
 public:
  SerialBlas() : previous_(omp_get_max_threads()) {
    omp_set_num_threads(1);
    if (openblas_.set) {
      previous_blas_ = openblas_.get();
      openblas_.set(1);
    }
  }
  ~SerialBlas() {
    omp_set_num_threads(previous_);
    if (openblas_.set) openblas_.set(previous_blas_);
  }
  SerialBlas(const SerialBlas&) = delete;
  SerialBlas& operator=(const SerialBlas&) = delete;

 private:
  /// OpenBLAS's thread control, when the BLAS loaded is OpenBLAS.
  struct OpenBlas {
    void (*set)(int) = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    int (*get)() = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    OpenBlas() {
      if (!get) set = nullptr;
    }
  };
  static inline const OpenBlas openblas_;
  int previous_, previous_blas_ = 1;
};

class CholmodSolver final : public LinearSolver {
 public:
  explicit CholmodSolver(const LinearSolverSettings& settings) : settings_(settings) {
    cholmod_start(&common_);
    common_.print = 0;
  }
  ~CholmodSolver() override {
    if (factor_) cholmod_free_factor(&factor_, &common_);
    cholmod_finish(&common_);
  }
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;

  void factorize(const SparseMatrix& A) override {
    current_ = &A;
    const bool same_pattern = factor_ && rows_ == A.rows && nonzeros_ == A.nonzeros();
    lagged_ = false;
    // An unchanged matrix (Hooke's implicit step, a constant tangent) keeps its factor.
    if (same_pattern && factorized_values_ == A.values) return;
    // A changed one first tries CG preconditioned by the old factor (solve()),
    // unless the last such solves cost more than a new factor would.
    if (same_pattern && settings_.reuse_iterations > 0 && !reuse_.refactorize()) {
      lagged_ = true;
      return;
    }
    factorize_now(A);
  }

  int solve(std::span<const double> b, std::span<double> x, double tolerance) override {
    if (lagged_) {
      const auto old_factor = [this](std::span<const double> r, std::span<double> z) { direct_solve(r, z); };
      const detail::PcgResult result =
          detail::preconditioned_cg(*current_, b, x, old_factor, tolerance, settings_.reuse_iterations, workspace_);
      if (result.converged) {
        reuse_.lagged_solve(result.iterations);
        return result.iterations;
      }
      factorize_now(*current_);  // drifted too far: a fresh factor
    }
    direct_solve(b, x);
    return 1;
  }

  std::string name() const override { return simplicial_ ? "cholmod (simplicial LDL^T)" : "cholmod"; }
  int factorizations() const override { return factorizations_; }

  /// [simplicial, factorisations, 3 reuse counts, the factorised values...], empty before a factor.
  std::vector<double> save_state() const override {
    if (factorized_values_.empty()) return {};
    const std::array<double, 3> counts = reuse_.saved();
    std::vector<double> saved = {simplicial_ ? 1.0 : 0.0, double(factorizations_), counts[0], counts[1], counts[2]};
    saved.insert(saved.end(), factorized_values_.begin(), factorized_values_.end());
    return saved;
  }

  void restore_state(std::span<const double> saved, const SparseMatrix& pattern) override {
    if (saved.empty()) return;
    if (saved.size() != kSavedCounts + pattern.values.size())
      throw InputError("the saved sparse Cholesky state holds " + std::to_string(saved.size()) +
                       " numbers; this model's matrix needs " + std::to_string(kSavedCounts + pattern.values.size()));
    SparseMatrix A = pattern;
    A.values.assign(saved.begin() + kSavedCounts, saved.end());
    simplicial_ = saved[0] != 0.0;  // the run had fallen back to LDL^T: analyse the same way
    factorize_now(A);
    factorizations_ = static_cast<int>(saved[1]);
    reuse_.restore({saved[2], saved[3], saved[4]});
  }

 private:
  void factorize_now(const SparseMatrix& A) {
    cholmod_sparse view = view_of(A);
    const SerialBlas serial;
    if (!factor_ || rows_ != A.rows || nonzeros_ != A.nonzeros())
      analyse(view, simplicial_ ? CHOLMOD_SIMPLICIAL : CHOLMOD_AUTO);
    rows_ = A.rows;
    nonzeros_ = A.nonzeros();
    factorized_values_.clear();
    lagged_ = false;
    cholmod_factorize(&view, factor_, &common_);
    if (common_.status == CHOLMOD_NOT_POSDEF && !simplicial_) {
      // Not positive definite (buckling, compressed StVK): LDL^T without
      // pivoting still solves most indefinite tangents a Newton step meets.
      simplicial_ = true;
      analyse(view, CHOLMOD_SIMPLICIAL);
      cholmod_factorize(&view, factor_, &common_);
    }
    if (common_.status != CHOLMOD_OK || factor_->minor < factor_->n)
      throw NumericalError("sparse Cholesky failed: the stiffness matrix is singular (column " +
                           std::to_string(factor_->minor) + " of " + std::to_string(factor_->n) +
                           "); is the body constrained?");
    factorized_values_ = A.values;
    reuse_.factorized();
    ++factorizations_;
  }

  void direct_solve(std::span<const double> b, std::span<double> x) {
    cholmod_dense rhs{};
    rhs.nrow = rhs.nzmax = rhs.d = b.size();
    rhs.ncol = 1;
    rhs.x = const_cast<double*>(b.data());
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    const SerialBlas serial;
    cholmod_dense* solution = cholmod_solve(CHOLMOD_A, factor_, &rhs, &common_);
    if (!solution) throw NumericalError("sparse Cholesky solve failed");
    std::memcpy(x.data(), solution->x, sizeof(double) * x.size());
    cholmod_free_dense(&solution, &common_);
  }

  void analyse(cholmod_sparse& view, int supernodal) {
    if (factor_) cholmod_free_factor(&factor_, &common_);
    common_.supernodal = supernodal;
    common_.final_ll = supernodal == CHOLMOD_SIMPLICIAL ? 0 : 1;
    factor_ = cholmod_analyze(&view, &common_);
    if (!factor_) throw NumericalError("CHOLMOD analysis failed (out of memory?)");
  }

  static constexpr std::size_t kSavedCounts = 5;
  LinearSolverSettings settings_;
  cholmod_common common_{};
  cholmod_factor* factor_ = nullptr;
  const SparseMatrix* current_ = nullptr;
  int rows_ = -1, nonzeros_ = -1;
  std::vector<double> factorized_values_;
  bool simplicial_ = false, lagged_ = false;
  int factorizations_ = 0;
  detail::PcgWorkspace workspace_;
  detail::FactorReusePolicy reuse_;
};

}  // namespace

std::unique_ptr<LinearSolver> make_cholmod_solver(const LinearSolverSettings& settings) {
  return std::make_unique<CholmodSolver>(settings);
}

}  // namespace tensormass
