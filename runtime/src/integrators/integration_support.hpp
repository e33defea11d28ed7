// Helpers shared by the integrators (internal header).
#ifndef TENSORMASS_INTEGRATORS_INTEGRATION_SUPPORT_HPP
#define TENSORMASS_INTEGRATORS_INTEGRATION_SUPPORT_HPP

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "common/phase_timer.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/integrators/integrators.hpp"
#include "tensormass/parallel/distribution.hpp"
#include "tensormass/parallel/mpi_world.hpp"

namespace tensormass::detail {

/// The rows of the state this rank computes and the sums over them. On one
/// process, or with the whole state on every rank: every row, and the sums
/// of the serial code (the same bits). With a divided state
/// (Distribution::divides_state): this rank's own rows, each sum taken here
/// and then over the ranks (the same bits on every rank), and the ghost
/// rows received from their owners after each update that needs them.
class StateRows {
 public:
  explicit StateRows(const Assembler& assembler)
      : model_(assembler.model()),
        divided_(assembler.distribution() && assembler.distribution()->divides_state() ? assembler.distribution()
                                                                                       : nullptr) {}

  bool divided() const { return divided_ != nullptr; }
  /// f(i) for each free index i this rank computes, ascending.
  template <class F>
  void for_each_free(F&& f) const {
    if (!divided_) {
      for (int i = 0; i < model_.free_dof_count(); ++i) f(i);
      return;
    }
    for (int i : divided_->owned_free_rows()) f(i);
  }
  /// Free index i's index among the whole mesh's free dofs (i on one process).
  int whole_free_row(int i) const { return divided_ ? divided_->whole_free_row(i) : i; }
  /// a.b over the free dofs (vectors free_dof_count long).
  double dot_free(std::span<const double> a, std::span<const double> b) const {
    if (!divided_) return dot(a, b);
    double sum = 0.0;
    for (int i : divided_->owned_free_rows()) sum += a[i] * b[i];
    return parallel::sum_over_ranks(sum);
  }
  double norm_free(std::span<const double> a) const { return std::sqrt(dot_free(a, a)); }
  /// a.b over all dofs (vectors dof_count long).
  double dot_dofs(std::span<const double> a, std::span<const double> b) const {
    if (!divided_) return dot(a, b);
    const std::size_t d = static_cast<std::size_t>(model_.dim());
    double sum = 0.0;
    for (int node : divided_->own_nodes())
      for (std::size_t k = d * node; k < d * node + d; ++k) sum += a[k] * b[k];
    return parallel::sum_over_ranks(sum);
  }
  double norm_dofs(std::span<const double> a) const { return std::sqrt(dot_dofs(a, a)); }
  /// The largest |a_i| over the free dofs.
  double max_abs_free(std::span<const double> a) const {
    double largest = 0.0;
    for_each_free([&](int i) { largest = std::max(largest, std::abs(a[i])); });
    return divided_ ? parallel::max_over_ranks(largest) : largest;
  }
  /// Whether `ok` holds on every rank.
  bool on_every_rank(bool ok) const { return divided_ ? parallel::sum_over_ranks(ok ? 0.0 : 1.0) == 0.0 : ok; }
  /// The ghost rows of dof vectors (one or two) and of free-dof vectors, from their owners.
  void share_ghost_dofs(std::span<double> a, std::span<double> b = {}) const {
    if (divided_) divided_->share_ghost_dofs(a, b);
  }
  void share_ghost_free(std::span<double> v) const {
    if (divided_) divided_->share_ghost_free(v);
  }

 private:
  const Model& model_;
  const Distribution* divided_;
};

/// Assembles g(u) (and K when given), timed as assembly.
inline void assemble(Integration& run, std::span<const double> u, std::span<double> g, SparseMatrix* K) {
  PhaseTimer timer(run.statistics.assembly_seconds);
  run.assembler.assemble(u, g, K);
}

/// Factorises A and solves A x = b (x: initial guess in, solution out) to
/// the relative residual `tolerance` (default: the linear solver's
/// setting), timed as solve.
inline void linear_solve(Integration& run, const SparseMatrix& A, std::span<const double> b, std::span<double> x,
                         double tolerance = 0.0) {
  PhaseTimer timer(run.statistics.solve_seconds);
  const int factorizations = run.linear.factorizations();
  const std::vector<int>& changing = run.assembler.changing_rows();
  run.linear.set_changing_rows(changing, run.assembler.changing_rows_revision());
  run.linear.factorize(A);
  if (tolerance <= 0.0) tolerance = run.settings.linear.tolerance;
  run.statistics.linear_iterations += run.linear.solve(b, x, tolerance);
  run.statistics.factorizations += run.linear.factorizations() - factorizations;
  for (std::string& warning : run.linear.take_warnings()) {
    if (parallel::world_rank() == 0) std::fprintf(stderr, "tensormass: warning: %s\n", warning.c_str());
    run.statistics.warnings.push_back(std::move(warning));
  }
}

inline double max_abs(std::span<const double> v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

/// Throws NumericalError when a value is NaN or infinite.
inline void require_finite(std::span<const double> values, const std::string& what) {
  for (double x : values)
    if (!std::isfinite(x)) throw NumericalError(what + " is not finite (NaN or infinity)");
}

/// require_finite on every rank when one rank's values fail: with a
/// divided state each rank checks the rows it holds.
inline void require_finite(const StateRows& rows, std::span<const double> values, const std::string& what) {
  bool finite = true;
  for (double x : values) finite = finite && std::isfinite(x);
  if (!rows.on_every_rank(finite)) throw NumericalError(what + " is not finite (NaN or infinity)");
}

/// Model::first_inverted_cell over every rank's cells: the cell's index
/// in the whole mesh and the rank that holds it, or value -1. The same
/// answer on every rank (collective over MPI ranks).
inline parallel::RankedValue first_inverted_cell(const Assembler& assembler, std::span<const double> u) {
  const Model& model = assembler.model();
  const int cell = model.first_inverted_cell(u);
  const Distribution* distribution = assembler.distribution();
  if (!distribution) return {cell, 0};
  const int none = distribution->whole_cell_count();
  const parallel::RankedValue first = parallel::min_over_ranks(cell < 0 ? none : distribution->global_cell(cell));
  return first.value == none ? parallel::RankedValue{-1, 0} : first;
}

inline bool any_cell_inverted(const Assembler& assembler, std::span<const double> u) {
  return first_inverted_cell(assembler, u).value >= 0;
}

/// Throws NumericalError naming the first inverted element and its law
/// (on every rank, with the message of the rank holding the cell).
inline void require_no_inversion(const Assembler& assembler, std::span<const double> u, const std::string& where) {
  const parallel::RankedValue first = first_inverted_cell(assembler, u);
  if (first.value < 0) return;
  const Model& model = assembler.model();
  std::string message;
  if (first.rank == parallel::world_rank()) {
    const int cell = model.first_inverted_cell(u);  // on this rank: the first in the whole mesh's order
    message = model.mesh().describe_cell(cell) + " inverted (det F <= 0) under law " + model.kernel(cell).law + " " +
              where + " (a law that cannot invert; stable_neohookean is defined through inversion)";
  }
  std::vector<char> text(message.begin(), message.end());
  parallel::broadcast_bytes_from(first.rank, text);
  throw NumericalError(std::string(text.begin(), text.end()));
}

}  // namespace tensormass::detail

#endif
