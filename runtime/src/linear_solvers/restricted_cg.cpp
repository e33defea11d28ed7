#include "linear_solvers/restricted_cg.hpp"

#include <cmath>
#include <cstring>

#include "tensormass/common/errors.hpp"

namespace tensormass::detail {

void ChangedBlock::multiply_add(std::span<const double> p, std::span<double> q) const {
  for (std::size_t i = 0; i < rows.size(); ++i) {
    double sum = 0.0;
    for (int k = start[i]; k < start[i + 1]; ++k) sum += values[k] * p[columns[k]];
    q[i] += sum;
  }
}

ChangedBlock changed_block(const SparseMatrix& A, std::span<const double> factorized) {
  ChangedBlock change;
  std::vector<int> index(A.rows, -1);
  for (int row = 0; row < A.rows; ++row) {
    const int first = A.row_start[row], count = A.row_start[row + 1] - first;
    // Bitwise: a -0.0 for a 0.0 adds a row whose difference is zero.
    if (std::memcmp(A.values.data() + first, factorized.data() + first, sizeof(double) * count) != 0) {
      index[row] = static_cast<int>(change.rows.size());
      change.rows.push_back(row);
    }
  }
  change.start.assign(1, 0);
  for (int row : change.rows) {
    for (int k = A.row_start[row]; k < A.row_start[row + 1]; ++k)
      if (const int column = index[A.columns[k]]; column >= 0 && A.values[k] != factorized[k]) {
        change.columns.push_back(column);
        change.values.push_back(A.values[k] - factorized[k]);
      }
    change.start.push_back(static_cast<int>(change.columns.size()));
  }
  return change;
}

namespace {

/// work[position of N's row i] = v[i].
void place_on_block(const FactorReach& reach, const ChangedBlock& change, std::span<const double> v,
                    std::span<double> work) {
  for (std::size_t i = 0; i < change.rows.size(); ++i) work[reach.position(change.rows[i])] = v[i];
}

/// out[i] = work[position of N's row i].
void read_block(const FactorReach& reach, const ChangedBlock& change, std::span<const double> work,
                std::span<double> out) {
  for (std::size_t i = 0; i < change.rows.size(); ++i) out[i] = work[reach.position(change.rows[i])];
}

/// out = (F^-1 E v)|N: v placed on N, both substitutions over the selection.
void solve_on_block(const FactorReach& reach, const ChangedBlock& change, std::span<const double> v,
                    std::span<double> out, std::vector<double>& work) {
  reach.clear_selected(work);
  place_on_block(reach, change, v, work);
  reach.forward(work, true);
  reach.backward(work, true);
  read_block(reach, change, work, out);
}

/// x = F^-1 (b + E w), from base = L^-1 P b.
void form_solution(const FactorReach& reach, const ChangedBlock& change, std::span<const double> w, std::span<double> x,
                   RestrictedWorkspace& ws) {
  std::fill(ws.work.begin(), ws.work.end(), 0.0);
  place_on_block(reach, change, w, ws.work);
  reach.forward(ws.work, true);
  for (std::size_t k = 0; k < ws.work.size(); ++k) ws.work[k] += ws.base[k];
  reach.backward(ws.work, false);
  reach.unpermute(ws.work, x);
}

}  // namespace

PcgResult restricted_cg(const FactorReach& reach, const ChangedBlock& change, std::span<const double> b,
                        std::span<double> x, double tolerance, int max_iterations, RestrictedWorkspace& ws) {
  const std::size_t n = b.size(), m = change.rows.size();
  ws.base.resize(n), ws.work.resize(n);
  for (auto* v : {&ws.w, &ws.r, &ws.z, &ws.p, &ws.t, &ws.q, &ws.x_n}) v->assign(m, 0.0);
  const double b_norm = norm(b);
  if (b_norm == 0.0) {
    std::fill(x.begin(), x.end(), 0.0);
    return {0, true, 0.0};
  }
  // w0 = -D x (the guess on N), then x0 on N and r0 = b - A x0 = -(w0 + D x0).
  for (std::size_t i = 0; i < m; ++i) ws.x_n[i] = x[change.rows[i]];
  change.multiply_add(ws.x_n, ws.q);
  for (std::size_t i = 0; i < m; ++i) ws.w[i] = -ws.q[i];
  reach.permute(b, ws.base);
  reach.forward(ws.base, false);
  reach.clear_selected(ws.work);
  place_on_block(reach, change, ws.w, ws.work);
  reach.forward(ws.work, true);
  for (std::size_t k = 0; k < n; ++k) ws.work[k] += ws.base[k];  // off the selection: not read
  reach.backward(ws.work, true);
  read_block(reach, change, ws.work, ws.x_n);
  std::fill(ws.q.begin(), ws.q.end(), 0.0);
  change.multiply_add(ws.x_n, ws.q);
  for (std::size_t i = 0; i < m; ++i) ws.r[i] = -(ws.w[i] + ws.q[i]);

  double residual = norm(ws.r);
  PcgResult result{max_iterations, false, residual / b_norm};
  if (residual <= tolerance * b_norm) result = {0, true, residual / b_norm};
  else {
    // t = F p is tracked on N: F z = r there and zero elsewhere, so A p = t + D p.
    solve_on_block(reach, change, ws.r, ws.z, ws.work);
    ws.p = ws.z;
    ws.t = ws.r;
    double rz = dot(ws.r, ws.z);
    for (int iteration = 1; iteration <= max_iterations; ++iteration) {
      ws.q = ws.t;
      change.multiply_add(ws.p, ws.q);
      const double alpha = rz / dot(ws.p, ws.q);
      for (std::size_t i = 0; i < m; ++i) {
        ws.w[i] += alpha * ws.t[i];
        ws.r[i] -= alpha * ws.q[i];
      }
      residual = norm(ws.r);
      if (!std::isfinite(residual)) throw NumericalError("conjugate gradients produced NaN (indefinite matrix?)");
      if (residual <= tolerance * b_norm) {
        result = {iteration, true, residual / b_norm};
        break;
      }
      solve_on_block(reach, change, ws.r, ws.z, ws.work);
      const double rz_next = dot(ws.r, ws.z);
      const double beta = rz_next / rz;
      rz = rz_next;
      for (std::size_t i = 0; i < m; ++i) {
        ws.p[i] = ws.z[i] + beta * ws.p[i];
        ws.t[i] = ws.r[i] + beta * ws.t[i];
      }
      result.relative_residual = residual / b_norm;
    }
  }
  form_solution(reach, change, ws.w, x, ws);
  return result;
}

}  // namespace tensormass::detail
