// The hand-written St Venant-Kirchhoff baseline: see handwritten_stvk.hpp.
// Deliberately plain: dense Voigt D, full (not symmetric-half) K, no CSE
// beyond what the loops naturally give.
#include "handwritten_stvk.hpp"

#include <cmath>

#include "tensormass/kernels/kernel_abi.h"

namespace tensormass::bench::handwritten {

namespace {

/// Rest Jacobian, its determinant and dN/dX = dN/dr J^{-1} at one point.
/// dNdr: N by 3. Writes w*det(J), then dN/dX (N by 3) to `point`.
template <int N>
int precompute_point(const double* X, const double (&dNdr)[N][3], double weight, double* point) {
  double J[3][3] = {};  // J[a][r] = dX_a/dr_r
  for (int j = 0; j < N; ++j)
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 3; ++r) J[a][r] += X[j * 3 + a] * dNdr[j][r];
  const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                     J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                     J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
  if (!(det > 0.0) || !std::isfinite(det)) return 1;
  double Jinv[3][3];  // Jinv[r][a] = dr_r/dX_a
  Jinv[0][0] = (J[1][1] * J[2][2] - J[1][2] * J[2][1]) / det;
  Jinv[0][1] = (J[0][2] * J[2][1] - J[0][1] * J[2][2]) / det;
  Jinv[0][2] = (J[0][1] * J[1][2] - J[0][2] * J[1][1]) / det;
  Jinv[1][0] = (J[1][2] * J[2][0] - J[1][0] * J[2][2]) / det;
  Jinv[1][1] = (J[0][0] * J[2][2] - J[0][2] * J[2][0]) / det;
  Jinv[1][2] = (J[0][2] * J[1][0] - J[0][0] * J[1][2]) / det;
  Jinv[2][0] = (J[1][0] * J[2][1] - J[1][1] * J[2][0]) / det;
  Jinv[2][1] = (J[0][1] * J[2][0] - J[0][0] * J[2][1]) / det;
  Jinv[2][2] = (J[0][0] * J[1][1] - J[0][1] * J[1][0]) / det;
  point[0] = weight * det;
  for (int j = 0; j < N; ++j)
    for (int c = 0; c < 3; ++c) {
      double sum = 0.0;
      for (int r = 0; r < 3; ++r) sum += dNdr[j][r] * Jinv[r][c];
      point[1 + j * 3 + c] = sum;
    }
  return 0;
}

void lame(const double* params, double* consts) {
  const double young = params[0], poisson = params[1];
  consts[0] = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson));  // lam
  consts[1] = young / (2.0 * (1.0 + poisson));                              // mu
}

/// One quadrature point: adds wV * P dN_j to f and, when K is not null,
/// wV * (B^T D B + geometric) to K (3N by 3N, row-major).
template <int N>
void stvk_point(const double* u, const double* point, double lam, double mu, double* f, double* K) {
  constexpr int n_dofs = 3 * N;
  const double wV = point[0];
  const double* dN = point + 1;  // dN[j*3 + c] = dN_j/dX_c

  // Deformation gradient F = I + sum_j u_j (x) dN_j.
  double F[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
  for (int j = 0; j < N; ++j)
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) F[a][c] += u[j * 3 + a] * dN[j * 3 + c];

  // Green-Lagrange strain E = (F^T F - I)/2 and S = lam tr(E) I + 2 mu E.
  double E[3][3];
  for (int c = 0; c < 3; ++c)
    for (int d = 0; d < 3; ++d) {
      double sum = 0.0;
      for (int a = 0; a < 3; ++a) sum += F[a][c] * F[a][d];
      E[c][d] = 0.5 * (sum - (c == d ? 1.0 : 0.0));
    }
  const double trE = E[0][0] + E[1][1] + E[2][2];
  double S[3][3];
  for (int c = 0; c < 3; ++c)
    for (int d = 0; d < 3; ++d) S[c][d] = 2.0 * mu * E[c][d] + (c == d ? lam * trE : 0.0);

  // P = F S, f_j += wV P dN_j.
  double P[3][3];
  for (int a = 0; a < 3; ++a)
    for (int d = 0; d < 3; ++d) {
      double sum = 0.0;
      for (int c = 0; c < 3; ++c) sum += F[a][c] * S[c][d];
      P[a][d] = sum;
    }
  for (int j = 0; j < N; ++j)
    for (int a = 0; a < 3; ++a) {
      double sum = 0.0;
      for (int c = 0; c < 3; ++c) sum += P[a][c] * dN[j * 3 + c];
      f[j * 3 + a] += wV * sum;
    }
  if (K == nullptr) return;

  // Nonlinear strain-displacement matrix B (Voigt: 11 22 33 23 13 12,
  // engineering shears): dE_voigt = B du.
  double B[6][n_dofs];
  for (int j = 0; j < N; ++j)
    for (int a = 0; a < 3; ++a) {
      const int col = j * 3 + a;
      const double* g = dN + j * 3;
      B[0][col] = F[a][0] * g[0];
      B[1][col] = F[a][1] * g[1];
      B[2][col] = F[a][2] * g[2];
      B[3][col] = F[a][1] * g[2] + F[a][2] * g[1];
      B[4][col] = F[a][0] * g[2] + F[a][2] * g[0];
      B[5][col] = F[a][0] * g[1] + F[a][1] * g[0];
    }
  // Isotropic elasticity matrix D (6 by 6).
  double D[6][6] = {};
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) D[i][k] = lam;
    D[i][i] = lam + 2.0 * mu;
    D[i + 3][i + 3] = mu;
  }
  double DB[6][n_dofs];
  for (int i = 0; i < 6; ++i)
    for (int col = 0; col < n_dofs; ++col) {
      double sum = 0.0;
      for (int k = 0; k < 6; ++k) sum += D[i][k] * B[k][col];
      DB[i][col] = sum;
    }
  // Material part B^T D B.
  for (int row = 0; row < n_dofs; ++row)
    for (int col = 0; col < n_dofs; ++col) {
      double sum = 0.0;
      for (int i = 0; i < 6; ++i) sum += B[i][row] * DB[i][col];
      K[row * n_dofs + col] += wV * sum;
    }
  // Geometric part (dN_j . S dN_k) I.
  for (int j = 0; j < N; ++j)
    for (int k = 0; k < N; ++k) {
      double sum = 0.0;
      for (int c = 0; c < 3; ++c)
        for (int d = 0; d < 3; ++d) sum += dN[j * 3 + c] * S[c][d] * dN[k * 3 + d];
      for (int a = 0; a < 3; ++a) K[(j * 3 + a) * n_dofs + k * 3 + a] += wV * sum;
    }
}

template <int N, int Q>
void stvk_element(const double* u, const double* consts, double* f, double* K) {
  constexpr int n_dofs = 3 * N;
  for (int i = 0; i < n_dofs; ++i) f[i] = 0.0;
  if (K != nullptr)
    for (int i = 0; i < n_dofs * n_dofs; ++i) K[i] = 0.0;
  for (int q = 0; q < Q; ++q) stvk_point<N>(u, consts + 2 + q * (1 + 3 * N), consts[0], consts[1], f, K);
}

// Reference shape gradients.
constexpr double kTet4Gradients[4][3] = {{-1.0, -1.0, -1.0}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
constexpr double kHex8Signs[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                     {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

}  // namespace

int stvk_tet4_precompute(const double* rest_positions, const double* params, int param_count, double* consts) {
  if (param_count != 2) return TM_PRECOMPUTE_PARAM_COUNT;
  lame(params, consts);
  return precompute_point<4>(rest_positions, kTet4Gradients, 1.0 / 6.0, consts + 2);
}

void stvk_tet4_gradient(const double* u, const double* consts, double* gradient) {
  stvk_element<4, 1>(u, consts, gradient, nullptr);
}

void stvk_tet4_gradient_hessian(const double* u, const double* consts, double* gradient, double* hessian) {
  stvk_element<4, 1>(u, consts, gradient, hessian);
}

int stvk_hex8_precompute(const double* rest_positions, const double* params, int param_count, double* consts) {
  if (param_count != 2) return TM_PRECOMPUTE_PARAM_COUNT;
  lame(params, consts);
  const double g = 1.0 / std::sqrt(3.0);
  int q = 0;
  for (int it = 0; it < 2; ++it)
    for (int is = 0; is < 2; ++is)
      for (int ir = 0; ir < 2; ++ir, ++q) {
        const double point[3] = {ir ? g : -g, is ? g : -g, it ? g : -g};
        double dNdr[8][3];
        for (int j = 0; j < 8; ++j) {
          const double* s = kHex8Signs[j];
          const double f[3] = {1.0 + s[0] * point[0], 1.0 + s[1] * point[1], 1.0 + s[2] * point[2]};
          dNdr[j][0] = 0.125 * s[0] * f[1] * f[2];
          dNdr[j][1] = 0.125 * s[1] * f[0] * f[2];
          dNdr[j][2] = 0.125 * s[2] * f[0] * f[1];
        }
        if (precompute_point<8>(rest_positions, dNdr, 1.0, consts + 2 + q * (1 + 3 * 8)) != 0) return q + 1;
      }
  return 0;
}

void stvk_hex8_gradient(const double* u, const double* consts, double* gradient) {
  stvk_element<8, 8>(u, consts, gradient, nullptr);
}

void stvk_hex8_gradient_hessian(const double* u, const double* consts, double* gradient, double* hessian) {
  stvk_element<8, 8>(u, consts, gradient, hessian);
}

long stvk_flops_gradient(int nodes, int points) {
  const long n = nodes;
  const long F = 18 * n;         // 9 entries, n multiply-adds
  const long E = 9 * 6 + 9;      // F^T F (3 mult + 2 add... counted 6), minus I, halve
  const long S = 9 * 2 + 3 + 2;  // 2 mu E, + lam tr(E) on the diagonal
  const long P = 9 * 6;
  const long f = n * 3 * (6 + 2);  // P dN_j, times wV, accumulate
  return points * (F + E + S + P + f);
}

long stvk_flops_gradient_hessian(int nodes, int points) {
  const long n = nodes, dofs = 3 * n;
  const long B = dofs * 12;
  const long DB = 6 * dofs * 12;
  const long material = dofs * dofs * (12 + 2);
  const long geometric = n * n * (9 * 4 + 3 * 2);
  return stvk_flops_gradient(nodes, points) + points * (B + DB + material + geometric);
}

}  // namespace tensormass::bench::handwritten
