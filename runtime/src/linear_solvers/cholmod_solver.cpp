// Sparse Cholesky through the CHOLMOD C API (SuiteSparse), with the
// previous factor reused as a CG preconditioner while that is cheaper than
// a new one (a Newton or implicit step's tangent drifts slowly): see
// FactorReusePolicy. When the matrix changed on few rows (the cells under a
// non-linear law), that CG runs on those rows through the part of the
// factor they reach (restricted_cg). When only a block of the matrix
// changes (those cells' rows: set_changing_rows) and the old factor alone
// stops converging, an exact factor of that block corrects it (two_level_solve)
// before a whole new factor is paid for. When that block is too large (most
// cells non-linear), the block of the rows that jumped since the whole
// factorisation (cells that switched law) corrects it instead.
// At a whole factorisation, the changing rows and two rings of their
// neighbours are ordered after all other rows (region_last_ordering), so
// that the restricted CG's substitutions run over the region's supernodes
// only, while that ordering's factorisation costs at most twice CHOLMOD's.
#include <cholmod.h>
#include <dlfcn.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <vector>

#include "linear_solvers/cholmod_view.hpp"
#include "linear_solvers/factor_reach.hpp"
#include "linear_solvers/factor_reuse_policy.hpp"
#include "linear_solvers/preconditioned_cg.hpp"
#include "linear_solvers/region_last_ordering.hpp"
#include "linear_solvers/restricted_cg.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"

namespace tensormass {

namespace {

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
    // OpenBLAS first: its openmp variant sets OpenMP's count to its own
    // (the cores), which would undo the run's solver.threads.
    if (openblas_.set) openblas_.set(previous_blas_);
    omp_set_num_threads(previous_);
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
    if (local_factor_) cholmod_free_factor(&local_factor_, &common_);
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
      // The correction stays on: the changing block is refreshed; a block of
      // jumped rows is kept as factorised (it still preconditions well).
      if (local_ready_ && !local_from_jumps_) local_ready_ = factorize_local_block(A);
      return;
    }
    factorize_now(A);
  }

  void set_changing_rows(std::span<const int> rows, long revision) override {
    if (revision == local_revision_) return;
    local_revision_ = revision;
    changing_rows_.assign(rows.begin(), rows.end());
    local_pattern_stale_ = true;  // the correction, when on, is made for the new block at the next matrix
  }

  int solve(std::span<const double> b, std::span<double> x, double tolerance) override {
    if (lagged_) {
      // The old factor alone while it converges. Once it does not, the old
      // factor corrected by an exact factor of the changing block
      // (two_level_solve), kept on for the next matrices (the block
      // factorised for each) until the next whole factorisation, which
      // follows when that does not converge either. When the changing block
      // is too large, the block of the rows that jumped takes its place; it
      // is kept as factorised, and made again from the rows that jumped by
      // then when it stops converging, before a whole factorisation.
      const auto old_factor = [this](std::span<const double> r, std::span<double> z) { direct_solve(r, z); };
      const auto two_level = [this](std::span<const double> r, std::span<double> z) { two_level_solve(r, z); };
      int iterations = 0;
      double cost = 0.0;  // in whole solves with the old factor
      const auto converges = [&](const auto& precondition) {
        const detail::PcgResult result =
            detail::preconditioned_cg(*current_, b, x, precondition, tolerance, settings_.reuse_iterations, workspace_);
        iterations += result.iterations;
        cost += result.iterations;
        return result.converged;
      };
      bool done;
      if (local_ready_) done = converges(two_level);
      else if (const auto on_changed_rows = converges_on_changed_rows(b, x, tolerance, iterations, cost))
        done = *on_changed_rows;
      else done = converges(old_factor);
      if (!done && (!local_ready_ || local_from_jumps_)) {
        // Rows jumped since the block was made: make it again from them.
        local_ready_ = (!local_from_jumps_ && factorize_local_block(*current_)) || factorize_jumped_block(*current_);
        done = local_ready_ && converges(two_level);
      }
      if (done) {
        reuse_.lagged_solve(cost);
        return iterations;
      }
      factorize_now(*current_);  // drifted too far: a fresh factor
    }
    direct_solve(b, x);
    return 1;
  }

  std::string name() const override { return simplicial_ ? "cholmod (simplicial LDL^T)" : "cholmod"; }
  int factorizations() const override { return factorizations_; }

  /// [simplicial, factorisations, 3 reuse counts, block correction on,
  /// m, q, region ordered, smallest region refused (-1: none), then the q
  /// rows the ordering was chosen for, then when region ordered the
  /// factor's permutation (n rows), then for a block of jumped rows its m
  /// rows and its factorised values, then the whole factorised values...],
  /// empty before a factor.
  std::vector<double> save_state() const override {
    if (factorized_values_.empty()) return {};
    const std::array<double, 3> counts = reuse_.saved();
    const bool jumped = local_ready_ && local_from_jumps_;
    const double refused = smallest_refused_region_ == kNoRegion ? -1.0 : double(smallest_refused_region_);
    std::vector<double> saved = {simplicial_ ? 1.0 : 0.0,
                                 double(factorizations_),
                                 counts[0],
                                 counts[1],
                                 counts[2],
                                 local_ready_ ? 1.0 : 0.0,
                                 jumped ? double(local_rows_.size()) : 0.0,
                                 double(ordered_rows_.size()),
                                 region_ordered_ ? 1.0 : 0.0,
                                 refused};
    saved.insert(saved.end(), ordered_rows_.begin(), ordered_rows_.end());
    if (region_ordered_) {
      const int* perm = static_cast<const int*>(factor_->Perm);
      saved.insert(saved.end(), perm, perm + factor_->n);
    }
    if (jumped) {
      saved.insert(saved.end(), local_rows_.begin(), local_rows_.end());
      saved.insert(saved.end(), local_.values.begin(), local_.values.end());
    }
    saved.insert(saved.end(), factorized_values_.begin(), factorized_values_.end());
    return saved;
  }

  void restore_state(std::span<const double> saved, const SparseMatrix& pattern) override {
    if (saved.empty()) return;
    const auto count = [&](std::size_t k) {
      return saved.size() >= kSavedCounts ? static_cast<std::size_t>(std::max(saved[k], 0.0)) : 0;
    };
    const std::size_t rows = count(6), ordered = count(7), n = static_cast<std::size_t>(pattern.rows);
    const std::size_t permuted = count(8) != 0 ? n : 0, whole = pattern.values.size();
    const std::size_t head = kSavedCounts + ordered + permuted;
    if (saved.size() < head + rows + whole || rows > n || ordered > n)
      throw InputError("the saved sparse Cholesky state holds " + std::to_string(saved.size()) +
                       " numbers; this model's matrix needs at least " + std::to_string(head + rows + whole));
    SparseMatrix A = pattern;
    A.values.assign(saved.end() - static_cast<std::ptrdiff_t>(whole), saved.end());
    simplicial_ = saved[0] != 0.0;  // the run had fallen back to LDL^T: analyse the same way
    const auto rows_at = [&](std::size_t from, std::size_t size) {
      std::vector<int> list(size);
      for (std::size_t i = 0; i < size; ++i) list[i] = static_cast<int>(saved[from + i]);
      if (std::any_of(list.begin(), list.end(), [&](int row) { return row < 0 || row >= pattern.rows; }))
        throw InputError("the saved sparse Cholesky state names a row outside this model's matrix");
      return list;
    };
    std::vector<int> perm = rows_at(kSavedCounts + ordered, permuted);
    {
      cholmod_sparse view = detail::cholmod_view_of(A);
      const SerialBlas serial;
      analyse(view, simplicial_ ? CHOLMOD_SIMPLICIAL : CHOLMOD_AUTO);
      if (!perm.empty()) analyse_given(view, perm, false), region_ordered_ = true;
      ordered_rows_ = rows_at(kSavedCounts, ordered);
      if (region_ordered_) mark_region(detail::dilated_rows(A, ordered_rows_, kRegionRings), A.rows);
      smallest_refused_region_ = saved[9] < 0.0 ? kNoRegion : static_cast<std::size_t>(saved[9]);
      factorize_values(view, A);
    }
    factorizations_ = static_cast<int>(saved[1]);
    reuse_.restore({saved[2], saved[3], saved[4]});
    local_ready_ = saved[5] != 0.0;  // made for the next matrix's block, as in the run that saved it
    if (rows > 0) restore_jumped_block(saved.subspan(head), rows, A);
    else if (saved.size() != head + whole)
      throw InputError("the saved sparse Cholesky state holds " + std::to_string(saved.size()) +
                       " numbers; this model's matrix needs " + std::to_string(head + whole));
  }

 private:
  void factorize_now(const SparseMatrix& A) {
    cholmod_sparse view = detail::cholmod_view_of(A);
    const SerialBlas serial;
    if (!factor_ || rows_ != A.rows || nonzeros_ != A.nonzeros())
      analyse(view, simplicial_ ? CHOLMOD_SIMPLICIAL : CHOLMOD_AUTO);
    if (!simplicial_ && !changing_rows_.empty() && !ordering_holds()) order_region_last(view, A);
    factorize_values(view, A);
  }

  /// factor_ (analysed) factorised with A's values.
  void factorize_values(cholmod_sparse& view, const SparseMatrix& A) {
    reach_.reset();  // made again on the new factor
    rows_ = A.rows;
    nonzeros_ = A.nonzeros();
    factorized_values_.clear();
    lagged_ = false;
    local_ready_ = false;
    local_from_jumps_ = false;
    cholmod_factorize(&view, factor_, &common_);
    if (common_.status == CHOLMOD_NOT_POSDEF && !simplicial_) {
      // Not positive definite (buckling, compressed StVK): LDL^T without
      // pivoting still solves most indefinite tangents a Newton step meets.
      simplicial_ = true;
      analyse(view, CHOLMOD_SIMPLICIAL);
      cholmod_factorize(&view, factor_, &common_);
    }
    if (common_.status != CHOLMOD_OK || factor_->minor < factor_->n) {
      nonzeros_ = -1;  // no factor to reuse: the next matrix is analysed and factorised afresh
      if (common_.status != CHOLMOD_OK && common_.status != CHOLMOD_NOT_POSDEF)
        throw NumericalError("sparse Cholesky failed (CHOLMOD status " + std::to_string(common_.status) + ")");
      throw NotPositiveDefiniteError("sparse Cholesky failed: the stiffness matrix is singular or indefinite (column " +
                                     std::to_string(factor_->minor) + " of " + std::to_string(factor_->n) +
                                     "); is the body constrained?");
    }
    factorized_values_ = A.values;
    if (factor_->is_super && factor_->is_ll) reach_.emplace(*factor_);
    reuse_.factorized();
    ++factorizations_;
  }

  /// factor_ analysed with the changing rows and kRegionRings rings of
  /// their neighbours ordered last (later changing rows within them keep
  /// that ordering: ordering_holds), when that region is at most
  /// kMaxRegionShare of the rows and its factorisation costs at most
  /// kMaxRegionFlopGrowth times CHOLMOD's own ordering's; else with
  /// CHOLMOD's. A region at least as large as one refused is not tried
  /// (regions grow as cells climb: their fill would grow too).
  void order_region_last(cholmod_sparse& view, const SparseMatrix& A) {
    ordered_rows_ = changing_rows_;
    const std::vector<int> region = detail::dilated_rows(A, changing_rows_, kRegionRings);
    mark_region(region, A.rows);
    if (region.size() <= kMaxRegionShare * A.rows && region.size() < smallest_refused_region_) {
      analyse_given(view, detail::region_last_ordering(A, region, common_), true);
      region_ordered_ = true;
      if (common_.fl <= kMaxRegionFlopGrowth * default_flops_) return;
      smallest_refused_region_ = region.size();
    }
    if (region_ordered_) analyse_given(view, default_perm_, false), region_ordered_ = false;
  }

  /// in_region_: 1 on `region`'s rows (of n).
  void mark_region(const std::vector<int>& region, int n) {
    in_region_.assign(n, 0);
    for (int row : region) in_region_[row] = 1;
  }
  /// Whether factor_'s ordering still fits the changing rows: chosen for
  /// them, or a region ordered last that holds them all.
  bool ordering_holds() const {
    if (changing_rows_ == ordered_rows_) return true;
    if (!region_ordered_) return false;
    return std::all_of(changing_rows_.begin(), changing_rows_.end(), [&](int row) { return in_region_[row] != 0; });
  }

  void direct_solve(std::span<const double> b, std::span<double> x) {
    cholmod_dense rhs = detail::cholmod_view_of(b);
    const SerialBlas serial;
    cholmod_dense* solution = cholmod_solve(CHOLMOD_A, factor_, &rhs, &common_);
    if (!solution) throw NumericalError("sparse Cholesky solve failed");
    std::memcpy(x.data(), solution->x, sizeof(double) * x.size());
    cholmod_free_dense(&solution, &common_);
  }

  /// CG preconditioned by the old factor on the rows where the matrix
  /// changed since it (restricted_cg), when the substitutions over the
  /// supernodes they reach cost at most kMaxReachShare of whole ones.
  /// Whether it converged; nothing where it does not apply.
  std::optional<bool> converges_on_changed_rows(std::span<const double> b, std::span<double> x, double tolerance,
                                                int& iterations, double& cost) {
    // The rows of the non-linear cells change at every matrix: when they
    // alone reach too much, the comparison of every value is spared.
    if (!reach_ || reach_->select(changing_rows_) > kMaxReachShare) return std::nullopt;
    const detail::ChangedBlock change = detail::changed_block(*current_, factorized_values_);
    const double share = reach_->select(change.rows);
    if (share > kMaxReachShare) return std::nullopt;
    // As many iterations as the whole-factor CG may take, in cost.
    const int cap = static_cast<int>(settings_.reuse_iterations / std::max(share, 0.05));
    const detail::PcgResult result = detail::restricted_cg(*reach_, change, b, x, tolerance, cap, restricted_);
    iterations += result.iterations;
    cost += 1.0 + share * result.iterations;  // x formed once, then each iteration on the reach
    return result.converged;
  }

  /// The changing block K_NN of A (rows and columns local_rows_) factorised
  /// afresh, when it is a small enough part of A and positive definite.
  bool factorize_local_block(const SparseMatrix& A) {
    const std::size_t rows = changing_rows_.size();
    if (rows == 0 || rows > kMaxLocalFraction * A.rows) return false;
    const SerialBlas serial;
    if (local_pattern_stale_) build_local_pattern(A, changing_rows_), local_pattern_stale_ = false;
    return refactorize_local_block(A);
  }

  /// The block of the rows that jumped since the whole factorisation (an
  /// entry moved by more than kJump of the row's diagonal: cells that
  /// switched law, where the tangent changes at once) factorised afresh,
  /// when that block is small enough. The rows of a whole non-linear region
  /// (factorize_local_block) are often too many; those that jumped are what
  /// the old factor cannot follow.
  bool factorize_jumped_block(const SparseMatrix& A) {
    std::vector<int> jumped;
    for (int row = 0; row < A.rows; ++row) {
      const double limit = kJump * std::abs(A.values[A.diagonal[row]]);
      for (int k = A.row_start[row]; k < A.row_start[row + 1]; ++k)
        if (std::abs(A.values[k] - factorized_values_[k]) > limit) {
          jumped.push_back(row);
          break;
        }
    }
    if (jumped.empty() || jumped.size() > kMaxLocalFraction * A.rows) return false;
    const SerialBlas serial;
    build_local_pattern(A, jumped);
    local_from_jumps_ = true;
    local_pattern_stale_ = true;  // a later block of the changing rows is built afresh
    if (refactorize_local_block(A)) return true;
    local_from_jumps_ = false;
    return false;
  }

  /// The block of jumped rows a checkpoint saved: `saved` holds its rows,
  /// its factorised values, then the whole matrix's.
  void restore_jumped_block(std::span<const double> saved, std::size_t rows, const SparseMatrix& pattern) {
    const std::vector<int> jumped(saved.begin(), saved.begin() + static_cast<std::ptrdiff_t>(rows));
    const SerialBlas serial;
    build_local_pattern(pattern, jumped);
    const std::size_t values = local_.values.size();
    if (saved.size() != rows + values + pattern.values.size())
      throw InputError("the saved sparse Cholesky state does not match this model's matrix (its block of " +
                       std::to_string(rows) + " rows)");
    std::copy_n(saved.begin() + static_cast<std::ptrdiff_t>(rows), values, local_.values.begin());
    local_from_jumps_ = true;
    local_pattern_stale_ = true;
    local_ready_ = factorize_local_values() && local_ready_;
  }

  /// local_ refilled from A and factorised, while that costs at most
  /// kMaxLocalFlopShare of a whole factorisation.
  bool refactorize_local_block(const SparseMatrix& A) {
    const SerialBlas serial;
    // Worth it only while refactorising the block costs a small part of a
    // whole factorisation (CHOLMOD's flop counts from the two analyses).
    if (!(local_flops_ <= kMaxLocalFlopShare * factor_flops_)) return false;
    for (std::size_t k = 0; k < local_positions_.size(); ++k) local_.values[k] = A.values[local_positions_[k]];
    return factorize_local_values();
  }

  /// local_factor_ from local_'s values; whether it is positive definite.
  bool factorize_local_values() {
    cholmod_sparse view = detail::cholmod_view_of(local_);
    cholmod_factorize(&view, local_factor_, &common_);
    return common_.status == CHOLMOD_OK && local_factor_->minor == local_factor_->n;
  }

  /// local_: A's entries between `rows`, in their order, and where each sits in A.values.
  void build_local_pattern(const SparseMatrix& A, const std::vector<int>& rows) {
    local_rows_ = rows;
    std::vector<int> local_index(A.rows, -1);
    for (std::size_t i = 0; i < local_rows_.size(); ++i) local_index[local_rows_[i]] = static_cast<int>(i);
    local_ = SparseMatrix{};
    local_.rows = static_cast<int>(local_rows_.size());
    local_.row_start.assign(1, 0);
    local_positions_.clear();
    for (int row : local_rows_) {
      for (int k = A.row_start[row]; k < A.row_start[row + 1]; ++k)
        if (const int column = local_index[A.columns[k]]; column >= 0) {
          local_.columns.push_back(column);
          local_positions_.push_back(k);
        }
      local_.row_start.push_back(static_cast<int>(local_.columns.size()));
    }
    local_.values.assign(local_.columns.size(), 0.0);
    local_neighbourhood_.clear();  // rows with an entry in a changing column
    for (int row = 0; row < A.rows; ++row)
      for (int k = A.row_start[row]; k < A.row_start[row + 1]; ++k)
        if (local_index[A.columns[k]] >= 0) {
          local_neighbourhood_.push_back(row);
          break;
        }
    if (local_factor_) cholmod_free_factor(&local_factor_, &common_);
    cholmod_sparse view = detail::cholmod_view_of(local_);
    common_.supernodal = CHOLMOD_AUTO;
    common_.final_ll = 1;
    local_factor_ = cholmod_analyze(&view, &common_);
    if (!local_factor_) throw NumericalError("CHOLMOD analysis of the changing block failed (out of memory?)");
    local_flops_ = common_.fl;
  }

  /// z = M^-1 r, symmetric multiplicative Schwarz: an exact solve on the
  /// changing block, the old factor on what remains of the residual, the
  /// changing block again.
  /// Only the rows that matter are multiplied: after the first local solve
  /// z lives on N, so A z has entries on N and its neighbours only; the last
  /// local solve reads the residual on N only.
  void two_level_solve(std::span<const double> r, std::span<double> z) {
    const int n = static_cast<int>(r.size());
    const SparseMatrix& A = *current_;
    residual_.assign(r.begin(), r.end());
    correction_.resize(n);
    std::fill(z.begin(), z.end(), 0.0);
    local_solve(r, z);
    for (int row : local_neighbourhood_) residual_[row] = r[row] - row_product(A, row, z);
    direct_solve(residual_, correction_);
    for (int i = 0; i < n; ++i) z[i] += correction_[i];
    for (int row : local_rows_) residual_[row] = r[row] - row_product(A, row, z);
    local_solve(residual_, z);
  }

  static double row_product(const SparseMatrix& A, int row, std::span<const double> x) {
    double sum = 0.0;
    for (int k = A.row_start[row]; k < A.row_start[row + 1]; ++k) sum += A.values[k] * x[A.columns[k]];
    return sum;
  }

  /// z[N] += K_NN^-1 r[N] over the changing rows N.
  void local_solve(std::span<const double> r, std::span<double> z) {
    const std::size_t m = local_rows_.size();
    local_rhs_.resize(m);
    for (std::size_t i = 0; i < m; ++i) local_rhs_[i] = r[local_rows_[i]];
    cholmod_dense rhs = detail::cholmod_view_of(std::span<const double>(local_rhs_));
    const SerialBlas serial;
    cholmod_dense* solution = cholmod_solve(CHOLMOD_A, local_factor_, &rhs, &common_);
    if (!solution) throw NumericalError("sparse Cholesky solve of the changing block failed");
    const double* values = static_cast<const double*>(solution->x);
    for (std::size_t i = 0; i < m; ++i) z[local_rows_[i]] += values[i];
    cholmod_free_dense(&solution, &common_);
  }

  /// factor_ analysed with CHOLMOD's own choice of ordering: the default
  /// ordering and its flops recorded, no region ordered or refused.
  void analyse(cholmod_sparse& view, int supernodal) {
    reach_.reset();  // it reads factor_
    if (factor_) cholmod_free_factor(&factor_, &common_);
    common_.supernodal = supernodal;
    common_.final_ll = supernodal == CHOLMOD_SIMPLICIAL ? 0 : 1;
    factor_ = cholmod_analyze(&view, &common_);
    if (!factor_) throw NumericalError("CHOLMOD analysis failed (out of memory?)");
    factor_flops_ = default_flops_ = common_.fl;
    const int* perm = static_cast<const int*>(factor_->Perm);
    default_perm_.assign(perm, perm + factor_->n);
    region_ordered_ = false;
    ordered_rows_.clear();
    smallest_refused_region_ = kNoRegion;  // a new pattern, or LDL^T from now on
  }

  /// factor_ analysed (supernodal LL^T) with the permutation `perm`
  /// (CHOLMOD's convention), postordered or as it is (a permutation a
  /// factor already had gives that factor's structure again).
  void analyse_given(cholmod_sparse& view, const std::vector<int>& perm, bool postorder) {
    reach_.reset();  // it reads factor_
    if (factor_) cholmod_free_factor(&factor_, &common_);
    common_.supernodal = CHOLMOD_AUTO;
    common_.final_ll = 1;
    common_.nmethods = 1;
    common_.method[0].ordering = CHOLMOD_GIVEN;
    common_.postorder = postorder;
    factor_ = cholmod_analyze_p(&view, const_cast<int*>(perm.data()), nullptr, 0, &common_);
    common_.nmethods = 0;  // CHOLMOD's own choice again for the other analyses
    common_.postorder = 1;
    if (!factor_) throw NumericalError("CHOLMOD analysis failed (out of memory?)");
    factor_flops_ = common_.fl;
  }

  static constexpr std::size_t kSavedCounts = 10;
  static constexpr std::size_t kNoRegion = static_cast<std::size_t>(-1);
  /// The region ordered last: the changing rows and this many rings of neighbours ...
  static constexpr int kRegionRings = 2;
  /// ... while it holds at most this share of the rows ...
  static constexpr double kMaxRegionShare = 0.5;
  /// ... and its factorisation costs at most this many times CHOLMOD's ordering's flops.
  static constexpr double kMaxRegionFlopGrowth = 2.0;
  /// The changing block gets its own factor up to this share of the rows.
  static constexpr double kMaxLocalFraction = 0.6;
  /// ... and while its factorisation costs at most this share of the whole one's flops.
  static constexpr double kMaxLocalFlopShare = 0.1;
  /// A row jumped when an entry moved by more than this share of its diagonal since the whole factorisation.
  static constexpr double kJump = 0.05;
  /// CG runs on the changed rows while their substitutions read at most this share of the factor.
  static constexpr double kMaxReachShare = 0.9;
  std::optional<detail::FactorReach> reach_;  ///< on factor_, when supernodal LL^T
  detail::RestrictedWorkspace restricted_;
  double factor_flops_ = 0.0, local_flops_ = 0.0;
  std::vector<int> default_perm_;  ///< CHOLMOD's own ordering of this pattern
  double default_flops_ = 0.0;     ///< its factorisation's flops
  std::vector<int> ordered_rows_;  ///< the changing rows factor_'s ordering was chosen for
  bool region_ordered_ = false;    ///< factor_ orders a region last
  std::vector<char> in_region_;    ///< when region_ordered_: 1 on the rows ordered last
  std::size_t smallest_refused_region_ = kNoRegion;
  std::vector<int> changing_rows_;  ///< the newest set (set_changing_rows)
  std::vector<int> local_rows_;     ///< the rows of the block factorised in local_factor_
  long local_revision_ = -1;
  bool local_pattern_stale_ = true, local_ready_ = false, local_from_jumps_ = false;
  SparseMatrix local_;
  std::vector<int> local_positions_, local_neighbourhood_;
  cholmod_factor* local_factor_ = nullptr;
  std::vector<double> local_rhs_, residual_, correction_;
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
