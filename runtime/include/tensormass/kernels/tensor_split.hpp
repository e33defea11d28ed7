/// \file tensor_split.hpp
/// The tensor split's loops (Tensor-Mass form), the same for every element
/// but for the compile-time sizes: D = dim, N = nodes, Q = quadrature points.
/// A generated tensor kernel supplies the element's tables, the law's
/// elasticity tensor CC and thin wrappers calling these templates.
///
/// A law quadratic in one strain measure, psi = 1/2 S:CC:S, makes the element
/// energy a polynomial in the nodal displacements u_j:
///   linear strain S = eps:  W = 1/2 u.K u
///   Green strain S = E:     W = 1/2 u.K u + sum_l sum_p m_p s_p (u_l . V_lp)
///                               + sum_pp' D'_pp' m_p s_p s_p',   s_p = u_j . u_k
/// over the node pairs p = (j, k), j <= k, with multiplicity m_p (1 if j == k,
/// else 2). The coefficients, per element after the point data:
///   K  dofs by dofs, K_ja,kb = sum_q w sum_ce CC_acbe G_jc G_ke
///   V  nodes by pairs by dim, V_lpa = 1/2 sum_q w sum_b G_lb (CC : X_p)_ab
///   D  pairs by pairs, D_pp' = 1/8 sum_q w m_p' (CC : X_p) : X_p'
/// with X_p = G_j G_k^T (G_j = dN_j/dX at the point).
#ifndef TENSORMASS_TENSOR_SPLIT_HPP
#define TENSORMASS_TENSOR_SPLIT_HPP

#include "tensormass/kernels/kernel_support.hpp"

// Every function here is forced inline into the generated entry points, as
// the loops were when the template wrote them out: an instance shared by
// kernels (a comdat function) is otherwise left out of line once it is large.
#if defined(__GNUC__)
#define TENSORMASS_TENSOR_INLINE [[gnu::always_inline]] inline
#else
#define TENSORMASS_TENSOR_INLINE inline
#endif

namespace tensormass::kernel::tensor {

/// The strain measure the law is quadratic in.
enum class Strain { linear, green };

/// The node pairs (j, k), j <= k, in row-major order, as compile-time tables.
template <int N>
struct NodePairs {
  static constexpr int count = N * (N + 1) / 2;
  int first[count] = {};
  int second[count] = {};
  double multiplicity[count] = {};  // 1 for j == k, else 2 (the pair stands for (j, k) and (k, j))
  int of[N][N] = {};                // of[j][k] = of[k][j]: the pair of nodes j and k
  constexpr NodePairs() {
    int p = 0;
    for (int j = 0; j < N; ++j)
      for (int k = j; k < N; ++k, ++p) {
        first[p] = j;
        second[p] = k;
        multiplicity[p] = j == k ? 1.0 : 2.0;
        of[j][k] = of[k][j] = p;
      }
  }
};

template <int N>
inline constexpr NodePairs<N> node_pairs{};

/// Sizes and offsets of the coefficient tensors (in doubles, from K).
template <int D, int N, Strain S>
struct Layout {
  static constexpr bool green = S == Strain::green;
  static constexpr int dofs = D * N;
  static constexpr int pairs = NodePairs<N>::count;
  static constexpr int k_size = dofs * dofs;
  static constexpr int v_size = green ? N * pairs * D : 0;
  static constexpr int d_size = green ? pairs * pairs : 0;
  static constexpr int offset_v = k_size;
  static constexpr int offset_d = k_size + v_size;
  static constexpr int total = k_size + v_size + d_size;
};

/// CC[a][b][c][e] of a row-major D^4 array.
template <int D>
TENSORMASS_TENSOR_INLINE double cc(const double* CC, int a, int b, int c, int e) {
  return CC[((a * D + b) * D + c) * D + e];
}

/// Adds one point's share (weight w, G^T the D by N shape gradients) to the coefficients.
template <int D, int N, Strain S>
TENSORMASS_TENSOR_INLINE void add_point_coefficients(double w, const double* GT, const double* CC,
                                                     double* coefficients) {
  using L = Layout<D, N, S>;
  constexpr auto& pairs = node_pairs<N>;
  constexpr int P = L::pairs;
  double* K = coefficients;
  for (int j = 0; j < N; ++j)
    for (int k = 0; k < N; ++k)
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) {
          double sum = 0.0;
          for (int c = 0; c < D; ++c)
            for (int e = 0; e < D; ++e) sum += cc<D>(CC, a, c, b, e) * GT[c * N + j] * GT[e * N + k];
          K[(j * D + a) * L::dofs + k * D + b] += w * sum;
        }
  if constexpr (L::green) {
    double* V = coefficients + L::offset_v;
    double* Dp = coefficients + L::offset_d;
    double X[P][D * D], M[P][D * D];  // X_p = G_j G_k^T, M_p = CC : X_p
    for (int p = 0; p < P; ++p) {
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) X[p][a * D + b] = GT[a * N + pairs.first[p]] * GT[b * N + pairs.second[p]];
      for (int c = 0; c < D; ++c)
        for (int e = 0; e < D; ++e) {
          double sum = 0.0;
          for (int a = 0; a < D; ++a)
            for (int b = 0; b < D; ++b) sum += X[p][a * D + b] * cc<D>(CC, a, b, c, e);
          M[p][c * D + e] = sum;
        }
    }
    for (int l = 0; l < N; ++l)
      for (int p = 0; p < P; ++p)
        for (int a = 0; a < D; ++a) {
          double sum = 0.0;
          for (int b = 0; b < D; ++b) sum += GT[b * N + l] * M[p][a * D + b];
          V[(l * P + p) * D + a] += 0.5 * w * sum;
        }
    for (int p = 0; p < P; ++p)
      for (int p2 = 0; p2 < P; ++p2) {
        double sum = 0.0;
        for (int i = 0; i < D * D; ++i) sum += M[p][i] * X[p2][i];
        Dp[p * P + p2] += 0.125 * w * pairs.multiplicity[p2] * sum;
      }
  }
}

/// The kernel's precompute after its parameters: the point data (w*det(J) and
/// G^T per point, as precompute_points writes them) at `out`, then the
/// coefficient tensors (Layout::total doubles). CC: the elasticity tensor,
/// D^4 row-major. Returns precompute_points' status (0, or the bad point + 1).
template <int D, int N, int Q, Strain S>
TENSORMASS_TENSOR_INLINE int precompute(const double* rest_positions, const double (&reference_gradients)[Q][N][D],
                                        const double (&weights)[Q], const double* CC, double* out) {
  const int status = precompute_points<D, N, Q>(rest_positions, reference_gradients, weights, out);
  if (status != 0) return status;
  constexpr int stride = 1 + D * N;
  double* coefficients = out + Q * stride;
  for (int i = 0; i < Layout<D, N, S>::total; ++i) coefficients[i] = 0.0;
  for (int q = 0; q < Q; ++q) {
    const double* point = out + q * stride;
    add_point_coefficients<D, N, S>(point[0], point + 1, CC, coefficients);
  }
  return 0;
}

/// (K u)_i for each dof i.
template <int D, int N>
TENSORMASS_TENSOR_INLINE void stiffness_times(const double* K, const double* u, double* Ku) {
  constexpr int dofs = D * N;
  for (int i = 0; i < dofs; ++i) {
    double sum = 0.0;
    for (int j = 0; j < dofs; ++j) sum += K[i * dofs + j] * u[j];
    Ku[i] = sum;
  }
}

/// The pair terms of the Green strain form at u: s[p] = u_j . u_k for each
/// pair p = (j, k), t[p] = sum_l u_l . V_lp and r[p] = sum_p' D'[p][p'] s[p']
/// (each array NodePairs<N>::count long).
template <int D, int N>
TENSORMASS_TENSOR_INLINE void pair_terms(const double* u, const double* coefficients, double* s, double* t, double* r) {
  using L = Layout<D, N, Strain::green>;
  constexpr auto& pairs = node_pairs<N>;
  constexpr int P = L::pairs;
  const double* V = coefficients + L::offset_v;
  const double* Dp = coefficients + L::offset_d;
  for (int p = 0; p < P; ++p) {
    double sum = 0.0;
    for (int a = 0; a < D; ++a) sum += u[pairs.first[p] * D + a] * u[pairs.second[p] * D + a];
    s[p] = sum;
  }
  for (int p = 0; p < P; ++p) {
    double tp = 0.0, rp = 0.0;
    for (int l = 0; l < N; ++l)
      for (int a = 0; a < D; ++a) tp += u[l * D + a] * V[(l * P + p) * D + a];
    for (int p2 = 0; p2 < P; ++p2) rp += Dp[p * P + p2] * s[p2];
    t[p] = tp;
    r[p] = rp;
  }
}

/// The element energy W(u).
template <int D, int N, Strain S>
TENSORMASS_TENSOR_INLINE double energy(const double* u, const double* coefficients) {
  const double* K = coefficients;
  constexpr int dofs = D * N;
  double W = 0.0;
  for (int i = 0; i < dofs; ++i) {
    double sum = 0.0;
    for (int j = 0; j < dofs; ++j) sum += K[i * dofs + j] * u[j];
    W += 0.5 * u[i] * sum;
  }
  if constexpr (S == Strain::green) {
    constexpr auto& pairs = node_pairs<N>;
    constexpr int P = NodePairs<N>::count;
    double s[P], t[P], r[P];
    pair_terms<D, N>(u, coefficients, s, t, r);
    for (int p = 0; p < P; ++p) W += pairs.multiplicity[p] * s[p] * (t[p] + r[p]);
  }
  return W;
}

/// The gradient dW/du into out (dofs).
template <int D, int N, Strain S>
TENSORMASS_TENSOR_INLINE void gradient(const double* u, const double* coefficients, double* out) {
  stiffness_times<D, N>(coefficients, u, out);
  if constexpr (S == Strain::green) {
    using L = Layout<D, N, S>;
    constexpr auto& pairs = node_pairs<N>;
    constexpr int P = L::pairs;
    const double* V = coefficients + L::offset_v;
    double s[P], t[P], r[P];
    pair_terms<D, N>(u, coefficients, s, t, r);
    for (int i = 0; i < N; ++i) {
      for (int p = 0; p < P; ++p) {
        const double weight = pairs.multiplicity[p] * s[p];
        for (int a = 0; a < D; ++a) out[i * D + a] += weight * V[(i * P + p) * D + a];
      }
      for (int k = 0; k < N; ++k) {
        const int p = pairs.of[i][k];
        const double weight = 2.0 * t[p] + 4.0 * r[p];
        for (int a = 0; a < D; ++a) out[i * D + a] += weight * u[k * D + a];
      }
    }
  }
}

/// The Hessian d2W/du2 into out (dofs by dofs, row-major); K alone for the linear strain.
template <int D, int N, Strain S>
TENSORMASS_TENSOR_INLINE void hessian(const double* u, const double* coefficients, double* out) {
  using L = Layout<D, N, S>;
  const double* K = coefficients;
  for (int i = 0; i < L::dofs * L::dofs; ++i) out[i] = K[i];
  if constexpr (!L::green) {
    (void)u;  // linear strain: the Hessian is the constant K
  } else {
    constexpr auto& pairs = node_pairs<N>;
    constexpr int P = L::pairs;
    const double* V = coefficients + L::offset_v;
    const double* Dp = coefficients + L::offset_d;
    double s[P], t[P], r[P];
    pair_terms<D, N>(u, coefficients, s, t, r);
    for (int i = 0; i < N; ++i)
      for (int n = 0; n < N; ++n) {
        double block[D][D] = {};
        const double diagonal = 2.0 * t[pairs.of[i][n]] + 4.0 * r[pairs.of[i][n]];
        for (int a = 0; a < D; ++a) block[a][a] = diagonal;
        for (int k = 0; k < N; ++k) {
          const double* v_i = V + (i * P + pairs.of[n][k]) * D;  // V_i,(n k)
          const double* v_n = V + (n * P + pairs.of[i][k]) * D;  // V_n,(i k)
          double y[D] = {};                                      // sum_m D_(ik)(nm) u_m
          for (int m = 0; m < N; ++m) {
            const int p2 = pairs.of[n][m];
            const double coefficient = Dp[pairs.of[i][k] * P + p2] / pairs.multiplicity[p2];
            for (int b = 0; b < D; ++b) y[b] += coefficient * u[m * D + b];
          }
          for (int a = 0; a < D; ++a)
            for (int b = 0; b < D; ++b)
              block[a][b] += 2.0 * (v_i[a] * u[k * D + b] + u[k * D + a] * v_n[b]) + 8.0 * u[k * D + a] * y[b];
        }
        for (int a = 0; a < D; ++a)
          for (int b = 0; b < D; ++b) out[(i * D + a) * L::dofs + n * D + b] += block[a][b];
      }
  }
}

}  // namespace tensormass::kernel::tensor

#endif
