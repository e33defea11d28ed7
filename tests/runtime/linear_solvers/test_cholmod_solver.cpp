// The CHOLMOD solver (cholmod_solver.cpp) on small SPD matrices: the
// requested tolerance is reached (looser = fewer iterations), it reuses its
// factor as a CG preconditioner for a matrix that drifted, corrects it with a factor of
// the block that changed when it is told which rows change (or, untold, of
// the rows that jumped), and factorises afresh when that stops paying or
// does not converge.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <memory>
#include <vector>

#include "grid_matrix.hpp"
#include "linear_solvers/region_last_ordering.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"

namespace {

using tensormass::LinearSolverSettings;
using tensormass::LinearSolverType;
using tensormass::SparseMatrix;
using tensormass::testing::laplacian;
using tensormass::testing::relative_residual;
using tensormass::testing::right_hand_side;

/// A CHOLMOD solver that has factorised `first` and solved with it once.
std::unique_ptr<tensormass::LinearSolver> cholmod_after_one_solve(const SparseMatrix& first,
                                                                  const std::vector<double>& b) {
  auto solver = tensormass::make_linear_solver(LinearSolverSettings{});
  std::vector<double> x(b.size(), 0.0);
  solver->factorize(first);
  solver->solve(b, x, 1e-10);
  return solver;
}

TEST(CholmodSolver, SolvesExactlyThenReusesItsFactorForADriftedMatrix) {
  constexpr int n = 200;
  auto solver = tensormass::make_linear_solver(LinearSolverSettings{});
  const std::vector<double> b = right_hand_side(n);
  std::vector<double> x(n, 0.0);
  const SparseMatrix A = laplacian(n, 0.01);
  solver->factorize(A);
  EXPECT_EQ(solver->solve(b, x, 1e-10), 1);
  EXPECT_LT(relative_residual(A, b, x), 1e-12);
  EXPECT_EQ(solver->factorizations(), 1);

  const SparseMatrix drifted = laplacian(n, 0.0105);
  solver->factorize(drifted);
  std::fill(x.begin(), x.end(), 0.0);
  const int iterations = solver->solve(b, x, 1e-10);
  EXPECT_GT(iterations, 1);  // CG preconditioned by the old factor
  EXPECT_LE(iterations, 12);
  EXPECT_LT(relative_residual(drifted, b, x), 1e-10);
  EXPECT_EQ(solver->factorizations(), 1);
}

// An indefinite matrix is a NotPositiveDefiniteError (static Newton shifts
// it: test_static_solver.cpp); the factor it left is not reused: the next
// matrix, of the same pattern, is factorised afresh and solved exactly.
TEST(CholmodSolver, RefusesAnIndefiniteMatrixThenFactorisesTheNextAfresh) {
  constexpr int n = 200;
  const std::vector<double> b = right_hand_side(n);
  auto solver = cholmod_after_one_solve(laplacian(n, 0.01), b);
  std::vector<double> x(n, 0.0);
  const SparseMatrix indefinite = laplacian(n, -1.0);  // eigenvalues 1 - 2 cos(k pi / (n + 1)): some negative
  EXPECT_THROW(
      {
        solver->factorize(indefinite);
        solver->solve(b, x, 1e-10);
      },
      tensormass::NotPositiveDefiniteError);
  const SparseMatrix next = laplacian(n, 0.0105);
  solver->factorize(next);
  std::fill(x.begin(), x.end(), 0.0);
  EXPECT_EQ(solver->solve(b, x, 1e-10), 1);  // a new factor: one direct solve
  EXPECT_LT(relative_residual(next, b, x), 1e-12);
}

TEST(CholmodSolver, LooserToleranceTakesFewerLaggedIterations) {
  constexpr int n = 200;
  const std::vector<double> b = right_hand_side(n);
  int iterations[2];
  const double tolerances[2] = {1e-10, 1e-3};
  for (int k = 0; k < 2; ++k) {
    const SparseMatrix first = laplacian(n, 0.01);
    auto solver = cholmod_after_one_solve(first, b);
    std::vector<double> x(n, 0.0);
    const SparseMatrix drifted = laplacian(n, 0.0105);
    solver->factorize(drifted);
    std::fill(x.begin(), x.end(), 0.0);
    iterations[k] = solver->solve(b, x, tolerances[k]);
    EXPECT_LT(relative_residual(drifted, b, x), tolerances[k]);
  }
  EXPECT_LT(iterations[1], iterations[0]);
}

TEST(CholmodSolver, RefactorisesAMatrixTooFarFromItsFactor) {
  constexpr int n = 200;
  const std::vector<double> b = right_hand_side(n);
  const SparseMatrix first = laplacian(n, 0.01);
  auto solver = cholmod_after_one_solve(first, b);
  std::vector<double> x(n, 0.0);
  const SparseMatrix far = laplacian(n, 1.0);  // the old factor is a poor preconditioner
  solver->factorize(far);
  std::fill(x.begin(), x.end(), 0.0);
  EXPECT_EQ(solver->solve(b, x, 1e-12), 1);
  EXPECT_EQ(solver->factorizations(), 2);
  EXPECT_LT(relative_residual(far, b, x), 1e-12);
}

/// laplacian(n, shift) with `extra` added to the diagonal of rows [first, last).
SparseMatrix with_stiffer_block(int n, double shift, int first, int last, double extra) {
  SparseMatrix A = laplacian(n, shift);
  for (int i = first; i < last; ++i) A.values[A.diagonal[i]] += extra;
  return A;
}

TEST(CholmodSolver, CorrectsItsOldFactorWithAFactorOfTheChangingBlock) {
  constexpr int n = 400, first = 100, last = 140;
  const std::vector<double> b = right_hand_side(n);
  std::vector<int> block;
  for (int i = first; i < last; ++i) block.push_back(i);
  auto solver = tensormass::make_linear_solver(LinearSolverSettings{});
  solver->set_changing_rows(block, 1);
  std::vector<double> x(n, 0.0);
  solver->factorize(laplacian(n, 0.01));
  solver->solve(b, x, 1e-10);
  // The block stiffens far past what the old factor can precondition in 12
  // iterations, twice: told which rows change, CHOLMOD corrects the old
  // factor with the block's own factor instead of factorising again.
  for (const double extra : {1.0, 3.0}) {
    const SparseMatrix changed = with_stiffer_block(n, 0.01, first, last, extra);
    solver->factorize(changed);
    std::fill(x.begin(), x.end(), 0.0);
    solver->solve(b, x, 1e-10);
    EXPECT_LT(relative_residual(changed, b, x), 1e-10) << "extra " << extra;
  }
  EXPECT_EQ(solver->factorizations(), 1);
}

/// laplacian(n, shift) with the diagonal of rows [first, last) raised by
/// `extra`, and of rows [first2, last2) by `extra2`.
SparseMatrix with_stiffer_blocks(int n, double shift, int first, int last, double extra, int first2, int last2,
                                 double extra2) {
  SparseMatrix A = with_stiffer_block(n, shift, first, last, extra);
  for (int i = first2; i < last2; ++i) A.values[A.diagonal[i]] += extra2;
  return A;
}

// Untold, the rows whose entries moved by more than 5 % of their diagonal
// since the factorisation (a cell that switched law) make the block. It is
// kept while it converges, and made again from the rows that jumped by
// then when a second block jumps. Without the correction this sequence
// costs 4 factorisations (each jump stops the old factor converging within
// 12 iterations).
TEST(CholmodSolver, CorrectsItsOldFactorWithAFactorOfTheRowsThatJumped) {
  constexpr int n = 2000;  // both blocks together within 10 % of a whole factorisation's flops
  const std::vector<double> b = right_hand_side(n);
  auto solver = tensormass::make_linear_solver(LinearSolverSettings{});
  std::vector<double> x(n, 0.0);
  solver->factorize(laplacian(n, 0.01));
  solver->solve(b, x, 1e-10);
  const std::vector<SparseMatrix> matrices = {
      with_stiffer_blocks(n, 0.01, 100, 140, 1.0, 0, 0, 0.0),       // the first block jumps
      with_stiffer_blocks(n, 0.01, 100, 140, 1.01, 0, 0, 0.0),      // drifts a little: the block is kept
      with_stiffer_blocks(n, 0.01, 100, 140, 1.01, 250, 290, 3.0),  // a second block jumps
      with_stiffer_blocks(n, 0.01, 100, 140, 3.0, 250, 290, 3.0)};  // the first jumps again
  for (std::size_t k = 0; k < matrices.size(); ++k) {
    solver->factorize(matrices[k]);
    std::fill(x.begin(), x.end(), 0.0);
    const int iterations = solver->solve(b, x, 1e-10);
    EXPECT_LT(relative_residual(matrices[k], b, x), 1e-10) << "matrix " << k;
    EXPECT_GT(iterations, 1) << "matrix " << k;  // CG, not a direct solve with a new factor
  }
  EXPECT_EQ(solver->factorizations(), 1);
}

// A checkpoint taken while the block of jumped rows is on: the restored
// solver solves the next matrices with the same iterations and the same bits.
TEST(CholmodSolver, RestoresItsBlockOfJumpedRowsBitForBit) {
  constexpr int n = 2000;
  const std::vector<double> b = right_hand_side(n);
  const SparseMatrix first = laplacian(n, 0.01);
  auto solver = tensormass::make_linear_solver(LinearSolverSettings{});
  std::vector<double> x(n, 0.0);
  solver->factorize(first);
  solver->solve(b, x, 1e-10);
  const SparseMatrix jumped = with_stiffer_blocks(n, 0.01, 100, 140, 1.0, 0, 0, 0.0);
  solver->factorize(jumped);
  solver->solve(b, x, 1e-10);
  const std::vector<double> saved = solver->save_state();
  ASSERT_GT(saved.size(), first.values.size() + 7 + 40);  // the block's rows and values are in
  auto restored = tensormass::make_linear_solver(LinearSolverSettings{});
  restored->restore_state(saved, first);
  std::vector<double> y = x;
  for (const double extra : {1.01, 1.02}) {
    const SparseMatrix next = with_stiffer_blocks(n, 0.01, 100, 140, extra, 0, 0, 0.0);
    solver->factorize(next);
    restored->factorize(next);
    EXPECT_EQ(solver->solve(b, x, 1e-10), restored->solve(b, y, 1e-10));
    EXPECT_EQ(x, y);
  }
  EXPECT_EQ(solver->factorizations(), restored->factorizations());
  // A state of the wrong size is refused with a message.
  std::vector<double> truncated(saved.begin(), saved.end() - 1);
  EXPECT_THROW(tensormass::make_linear_solver(LinearSolverSettings{})->restore_state(truncated, first),
               tensormass::InputError);
}

TEST(CholmodSolver, FactorisesAgainWhenMostRowsJumped) {
  constexpr int n = 400;
  const std::vector<double> b = right_hand_side(n);
  auto solver = tensormass::make_linear_solver(LinearSolverSettings{});
  std::vector<double> x(n, 0.0);
  solver->factorize(laplacian(n, 0.01));
  solver->solve(b, x, 1e-10);
  const SparseMatrix changed = with_stiffer_block(n, 0.01, 0, 300, 3.0);  // 75 % of the rows
  solver->factorize(changed);
  std::fill(x.begin(), x.end(), 0.0);
  EXPECT_EQ(solver->solve(b, x, 1e-10), 1);
  EXPECT_LT(relative_residual(changed, b, x), 1e-10);
  EXPECT_EQ(solver->factorizations(), 2);
}

TEST(CholmodSolver, RefactorisesOnceReuseCostsMoreThanTheMeanSolve) {
  constexpr int n = 400;
  LinearSolverSettings settings;
  settings.reuse_iterations = 1000;  // CG always converges: only the policy can ask for a new factor
  auto solver = tensormass::make_linear_solver(settings);
  const std::vector<double> b = right_hand_side(n);
  std::vector<double> x(n, 0.0);
  SparseMatrix A = laplacian(n, 0.001);
  solver->factorize(A);
  solver->solve(b, x, 1e-10);
  // A matrix drifting further each solve: lagged solves grow dearer, and the
  // policy factorises again before CG stops converging.
  int factorizations = 1;
  for (int k = 1; k <= 60 && factorizations == 1; ++k) {
    A = laplacian(n, 0.001 * (1.0 + 0.02 * k));
    solver->factorize(A);
    solver->solve(b, x, 1e-10);
    factorizations = solver->factorizations();
  }
  EXPECT_EQ(factorizations, 2);
}

TEST(CholmodSolver, SolvesAMatrixChangedOnFewRowsOnThoseRows) {
  // A 3D pattern (a supernodal factor) stiffened in a corner: CG runs on the
  // changed rows only (restricted_cg), and reaches the tolerance there.
  constexpr int side = 14;
  const SparseMatrix first = tensormass::testing::grid_laplacian(side, 0.1);
  const std::vector<double> b = right_hand_side(first.rows);
  auto solver = cholmod_after_one_solve(first, b);
  const SparseMatrix changed = tensormass::testing::stiffened(first, tensormass::testing::corner_rows(side, 5), 3.0);
  solver->factorize(changed);
  std::vector<double> x(b.size(), 0.0);
  const int iterations = solver->solve(b, x, 1e-10);
  EXPECT_GT(iterations, 1);  // more than 12 is allowed here: each reads part of the factor
  EXPECT_LT(relative_residual(changed, b, x), 1e-10);
  EXPECT_EQ(solver->factorizations(), 1);
}

// save_state()'s counts say which ordering the factor has: [7] the
// changing rows it was chosen for, [8] 1 when they (and two rings) are
// ordered last, [9] the smallest region refused for its fill (-1: none).
constexpr std::size_t kOrderedRows = 7, kRegionOrdered = 8, kRefusedRegion = 9;

/// A solver told `changing` (revision 1) that factorised and solved with A.
std::unique_ptr<tensormass::LinearSolver> cholmod_told(const std::vector<int>& changing, const SparseMatrix& A,
                                                       std::vector<double>& x, int reuse_iterations = 12) {
  LinearSolverSettings settings;
  settings.reuse_iterations = reuse_iterations;
  auto solver = tensormass::make_linear_solver(settings);
  solver->set_changing_rows(changing, 1);
  solver->factorize(A);
  const std::vector<double> b = tensormass::testing::uneven_vector(A.rows);
  std::fill(x.begin(), x.end(), 0.0);
  solver->solve(b, x, 1e-10);
  return solver;
}

TEST(CholmodSolver, OrdersSmallChangingRegionsLastAndSolvesAsBefore) {
  constexpr int kSide = 16;
  const SparseMatrix A = tensormass::testing::grid_laplacian(kSide, 0.1);
  const std::vector<double> b = tensormass::testing::uneven_vector(A.rows);
  const std::vector<int> centre = tensormass::testing::centre_rows(kSide, 2);
  std::vector<double> x(A.rows), untold_x(A.rows);
  auto solver = cholmod_told(centre, A, x, /*reuse_iterations=*/0);  // a whole factorisation for each matrix
  auto untold = cholmod_told({}, A, untold_x);
  const std::vector<double> state = solver->save_state();
  EXPECT_EQ(state[kOrderedRows], static_cast<double>(centre.size()));
  EXPECT_EQ(state[kRegionOrdered], 1.0);
  EXPECT_EQ(state[kRefusedRegion], -1.0);
  EXPECT_EQ(untold->save_state()[kRegionOrdered], 0.0);
  EXPECT_LT(relative_residual(A, b, x), 1e-10);
  for (int row = 0; row < A.rows; ++row) ASSERT_NEAR(x[row], untold_x[row], 1e-9 * std::abs(untold_x[row]));

  // Changing rows within the region ordered last keep its ordering; rows
  // beyond it get a new one at the next factorisation.
  const std::vector<int> within = tensormass::detail::dilated_rows(A, centre, 1);
  const std::vector<int> beyond = tensormass::testing::centre_rows(kSide, 6);
  for (const auto& [rows, ordered_for] : {std::pair{within, centre.size()}, std::pair{beyond, beyond.size()}}) {
    solver->set_changing_rows(rows, static_cast<long>(rows.size()));
    const SparseMatrix changed = tensormass::testing::stiffened(A, rows, 4.0);
    solver->factorize(changed);
    solver->solve(b, x, 1e-10);
    EXPECT_LT(relative_residual(changed, b, x), 1e-10);
    const std::vector<double> after = solver->save_state();
    EXPECT_EQ(after[kOrderedRows], static_cast<double>(ordered_for)) << rows.size() << " rows";
    EXPECT_EQ(after[kRegionOrdered], 1.0) << rows.size() << " rows";
  }
  EXPECT_EQ(solver->factorizations(), 3);

  // Most rows changing: CHOLMOD's own ordering again at the next factorisation.
  std::vector<int> most(A.rows * 3 / 5);
  for (std::size_t i = 0; i < most.size(); ++i) most[i] = static_cast<int>(i);
  solver->set_changing_rows(most, 2);
  const SparseMatrix stiffer = tensormass::testing::stiffened(A, most, 5.0);
  solver->factorize(stiffer);
  solver->solve(b, x, 1e-10);
  EXPECT_EQ(solver->save_state()[kRegionOrdered], 0.0);
  EXPECT_LT(relative_residual(stiffer, b, x), 1e-10);
}

// Rows scattered over the whole grid, ordered last, would fill a large
// dense trailing block: the solver keeps CHOLMOD's ordering (the same bits
// as a solver never told) and does not try a region as large again.
TEST(CholmodSolver, KeepsItsOwnOrderingWhenTheRegionWouldCostTooMuch) {
  constexpr int kSide = 16;
  const SparseMatrix A = tensormass::testing::grid_laplacian(kSide, 0.1);
  std::vector<int> scattered;
  for (int z = 2; z < kSide; z += 4)  // 4 x 4 x 4 rows
    for (int y = 2; y < kSide; y += 4)
      for (int x = 2; x < kSide; x += 4) scattered.push_back((z * kSide + y) * kSide + x);
  std::vector<double> x(A.rows), untold_x(A.rows);
  auto solver = cholmod_told(scattered, A, x);
  auto untold = cholmod_told({}, A, untold_x);
  const std::vector<double> state = solver->save_state();
  EXPECT_EQ(state[kRegionOrdered], 0.0);
  // The region: each row and the rows within two steps of it (a third of all).
  EXPECT_EQ(state[kRefusedRegion], static_cast<double>(tensormass::detail::dilated_rows(A, scattered, 2).size()));
  EXPECT_EQ(x, untold_x);
}

// A checkpoint taken with the region ordered last: the restored solver has
// the same factor and solves the next matrices with the same bits.
TEST(CholmodSolver, RestoresItsRegionOrderingBitForBit) {
  constexpr int kSide = 16;
  const SparseMatrix A = tensormass::testing::grid_laplacian(kSide, 0.1);
  const std::vector<double> b = tensormass::testing::uneven_vector(A.rows);
  const std::vector<int> centre = tensormass::testing::centre_rows(kSide, 3);
  std::vector<double> x(A.rows);
  auto solver = cholmod_told(centre, A, x);
  const std::vector<double> saved = solver->save_state();
  ASSERT_EQ(saved[kRegionOrdered], 1.0);
  auto restored = tensormass::make_linear_solver(LinearSolverSettings{});
  restored->restore_state(saved, A);
  EXPECT_EQ(restored->save_state(), saved);
  restored->set_changing_rows(centre, 7);  // a resumed run's revisions count afresh
  std::vector<double> y = x;
  for (const double extra : {0.5, 1.0, 4.0}) {
    const SparseMatrix next = tensormass::testing::stiffened(A, centre, extra);
    solver->factorize(next);
    restored->factorize(next);
    EXPECT_EQ(solver->solve(b, x, 1e-10), restored->solve(b, y, 1e-10)) << "extra " << extra;
    EXPECT_EQ(x, y) << "extra " << extra;
    EXPECT_LT(relative_residual(next, b, y), 1e-10) << "extra " << extra;
  }
  EXPECT_EQ(solver->factorizations(), restored->factorizations());
  // A state cut short is refused with a message.
  const std::vector<double> truncated(saved.begin(), saved.begin() + 12);
  EXPECT_THROW(tensormass::make_linear_solver(LinearSolverSettings{})->restore_state(truncated, A),
               tensormass::InputError);
}

TEST(CholmodSolver, LeavesTheCallersThreadCountAsItWas) {
  // CHOLMOD runs its BLAS on one thread; the OpenMP thread count the run
  // chose (solver.threads) must be the same afterwards. (OpenBLAS's
  // openmp variant sets OpenMP's count when its own is set back.)
  constexpr int n = 200;
  const int threads = omp_get_max_threads();
  const std::vector<double> b = right_hand_side(n);
  const SparseMatrix first = laplacian(n, 0.01), drifted = laplacian(n, 0.02);  // the solver keeps them
  for (const int requested : {1, 3, 2}) {
    omp_set_num_threads(requested);
    auto solver = cholmod_after_one_solve(first, b);
    std::vector<double> x(n, 0.0);
    solver->factorize(drifted);  // a lagged solve, then maybe a new factor
    solver->solve(b, x, 1e-10);
    EXPECT_EQ(omp_get_max_threads(), requested);
  }
  omp_set_num_threads(threads);
}

}  // namespace
