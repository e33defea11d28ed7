/// \file kernel_support.hpp
/// Small fixed-size loops shared by generated kernels (the law-specific code
/// is generated; these contractions are the same for every law). D = dim,
/// N = nodes; GT is the d by n transposed shape-gradient block of one point.
#ifndef TENSORMASS_KERNEL_SUPPORT_HPP
#define TENSORMASS_KERNEL_SUPPORT_HPP

#include <cmath>

#include "tensormass/kernels/polar_decomposition.hpp"

// Loops over the nodes are marked for vectorisation: with -fopenmp-simd (set
// by the build with TENSORMASS_SIMD) GCC vectorises them as loops instead of
// unrolling them into shuffles, 3x faster at 8 nodes.
#if defined(TENSORMASS_SIMD) || defined(_OPENMP)
#define TENSORMASS_SIMD_LOOP _Pragma("omp simd")
#else
#define TENSORMASS_SIMD_LOOP
#endif

namespace tensormass::kernel {

/// Fills, for each quadrature point, w*det(J) and G^T (D by N) from the rest
/// positions (N by D) and the reference gradients dN/dr (Q by N by D).
/// Returns 0, or q+1 for the first point with det(J) <= 0 or not finite.
template <int D, int N, int Q>
inline int precompute_points(const double* rest_positions, const double (&reference_gradients)[Q][N][D],
                             const double (&weights)[Q], double* out) {
  for (int q = 0; q < Q; ++q) {
    double J[D][D] = {};  // J[a][r] = dX_a/dr_r
    for (int j = 0; j < N; ++j)
      for (int a = 0; a < D; ++a)
        for (int r = 0; r < D; ++r) J[a][r] += rest_positions[j * D + a] * reference_gradients[q][j][r];
    double inverse[D][D];  // inverse[r][c] = dr_r/dX_c
    double det;
    if constexpr (D == 2) {
      det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
      inverse[0][0] = J[1][1] / det;
      inverse[0][1] = -J[0][1] / det;
      inverse[1][0] = -J[1][0] / det;
      inverse[1][1] = J[0][0] / det;
    } else {
      const double c00 = J[1][1] * J[2][2] - J[1][2] * J[2][1];
      const double c01 = J[1][2] * J[2][0] - J[1][0] * J[2][2];
      const double c02 = J[1][0] * J[2][1] - J[1][1] * J[2][0];
      det = J[0][0] * c00 + J[0][1] * c01 + J[0][2] * c02;
      inverse[0][0] = c00 / det;
      inverse[1][0] = c01 / det;
      inverse[2][0] = c02 / det;
      inverse[0][1] = (J[0][2] * J[2][1] - J[0][1] * J[2][2]) / det;
      inverse[1][1] = (J[0][0] * J[2][2] - J[0][2] * J[2][0]) / det;
      inverse[2][1] = (J[0][1] * J[2][0] - J[0][0] * J[2][1]) / det;
      inverse[0][2] = (J[0][1] * J[1][2] - J[0][2] * J[1][1]) / det;
      inverse[1][2] = (J[0][2] * J[1][0] - J[0][0] * J[1][2]) / det;
      inverse[2][2] = (J[0][0] * J[1][1] - J[0][1] * J[1][0]) / det;
    }
    // A flat element's det(J) is rounding noise of either sign: compare it with
    // the product of J's column lengths (the det of an orthogonal J of that size).
    double scale = 1.0;
    for (int r = 0; r < D; ++r) {
      double length2 = 0.0;
      for (int a = 0; a < D; ++a) length2 += J[a][r] * J[a][r];
      scale *= std::sqrt(length2);
    }
    if (!std::isfinite(det) || !(det > 64.0 * 2.220446049250313e-16 * scale)) return q + 1;
    double* point = out + q * (1 + D * N);
    point[0] = weights[q] * det;
    for (int c = 0; c < D; ++c)
      for (int j = 0; j < N; ++j) {
        double sum = 0.0;
        for (int r = 0; r < D; ++r) sum += reference_gradients[q][j][r] * inverse[r][c];
        point[1 + c * N + j] = sum;
      }
  }
  return 0;
}

/// H[a*D+c] = sum_j u[j*D+a] GT[c*N+j]: the displacement gradient at a point.
template <int D, int N>
inline void displacement_gradient(const double* u, const double* GT, double* H) {
  for (int a = 0; a < D; ++a)
    for (int c = 0; c < D; ++c) {
      double sum = 0.0;
      for (int j = 0; j < N; ++j) sum += u[j * D + a] * GT[c * N + j];
      H[a * D + c] = sum;
    }
}

/// g_a[j] += sum_c wP[a*D+c] GT[c*N+j], with g_by_component D by N.
template <int D, int N>
inline void accumulate_gradient(const double* wP, const double* GT, double (&g_by_component)[D][N]) {
  for (int a = 0; a < D; ++a)
    for (int c = 0; c < D; ++c) {
      const double p = wP[a * D + c];
      TENSORMASS_SIMD_LOOP
      for (int j = 0; j < N; ++j) g_by_component[a][j] += p * GT[c * N + j];
    }
}

template <int D, int N>
inline void scatter_gradient(const double (&g_by_component)[D][N], double* gradient) {
  for (int j = 0; j < N; ++j)
    for (int a = 0; a < D; ++a) gradient[j * D + a] = g_by_component[a][j];
}

/// Number of component pairs a <= b.
template <int D>
inline constexpr int component_pairs = D*(D + 1) / 2;

/// For each component pair (a <= b): K_ab[j][k] += sum_c GT[c][j] Z[c][k] with
/// Z[c][k] = sum_e wA[(a*D+c)][(b*D+e)] GT[e][k]; wA is the full D^2 by D^2
/// weighted tangent. Written as rank-D row updates over contiguous k with
/// restrict-qualified pointers and SIMD loops over k (a plain triple loop
/// was 3 to 6 times slower at N = 8).
template <int D, int N>
inline void accumulate_hessian(const double* __restrict__ wA, const double* __restrict__ GT,
                               double (&__restrict__ K_by_pair)[component_pairs<D>][N * N]) {
  constexpr int D2 = D * D;
  int pair = 0;
  for (int a = 0; a < D; ++a)
    for (int b = a; b < D; ++b, ++pair) {
      double Z[D][N];
      for (int c = 0; c < D; ++c) {
        double coefficient[D];
        for (int e = 0; e < D; ++e) coefficient[e] = wA[(a * D + c) * D2 + b * D + e];
        TENSORMASS_SIMD_LOOP
        for (int k = 0; k < N; ++k) {
          double sum = 0.0;
          for (int e = 0; e < D; ++e) sum += coefficient[e] * GT[e * N + k];
          Z[c][k] = sum;
        }
      }
      double* __restrict__ block = K_by_pair[pair];
      for (int j = 0; j < N; ++j) {
        double g[D];
        for (int c = 0; c < D; ++c) g[c] = GT[c * N + j];
        TENSORMASS_SIMD_LOOP
        for (int k = 0; k < N; ++k) {
          double sum = 0.0;
          for (int c = 0; c < D; ++c) sum += g[c] * Z[c][k];
          block[j * N + k] += sum;
        }
      }
    }
}

/// Writes the dofs by dofs row-major Hessian from the component-pair blocks.
template <int D, int N>
inline void scatter_hessian(const double (&K_by_pair)[component_pairs<D>][N * N], double* hessian) {
  constexpr int dofs = D * N;
  int pair = 0;
  for (int a = 0; a < D; ++a)
    for (int b = a; b < D; ++b, ++pair)
      for (int j = 0; j < N; ++j)
        for (int k = 0; k < N; ++k) {
          const double value = K_by_pair[pair][j * N + k];
          hessian[(j * D + a) * dofs + k * D + b] = value;
          hessian[(k * D + b) * dofs + j * D + a] = value;
        }
}

/// Copies the upper triangle of a row-major square matrix into its lower one.
template <int Size>
inline void mirror_upper(double* matrix) {
  for (int i = 0; i < Size; ++i)
    for (int j = 0; j < i; ++j) matrix[i * Size + j] = matrix[j * Size + i];
}

}  // namespace tensormass::kernel

#endif
