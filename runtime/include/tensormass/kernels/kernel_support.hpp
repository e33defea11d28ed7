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

// log with glibc's vector variants (libmvec), as <math.h> declares it under
// -ffast-math: a SIMD loop over a batch's lanes then takes the log of all of
// them in one call instead of one scalar call per lane (neo-Hookean's batched
// kernels). Set by the build (with -fno-math-errno and libmvec) for the
// kernels only; libmvec's log is within 4 ulp. Clang has no such attribute
// (its lanes call log one by one).
#if defined(TENSORMASS_VECTOR_LOG) && !defined(__clang__)
extern "C" double log(double) noexcept __attribute__((simd("notinbranch")));
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

// ---------------------------------------------------------------------------
// Batches: W elements at once in structure-of-arrays layout. Every batched
// array holds entry i of the batch's element (lane) l at [i*W + l], so a loop
// over the lanes is a loop over contiguous doubles and vectorises whatever
// the element's own loop sizes are.

/// The lanes per batch: one AVX register of doubles (also on AVX-512
/// machines), else an SSE2 pair. Callers read it from tm_kernel::batch_width.
/// On an AVX-512 machine 8 lanes ran the StVK tet4 kernel faster alone (0.51x
/// the per-element kernel against 0.72x with 4) but the assembly slower (1.05x
/// against 0.95x): the larger batch buffers push the sparse matrix's lines
/// out of L1 between scatters.
#if defined(__AVX__)
inline constexpr int kBatchWidth = 4;
#else
inline constexpr int kBatchWidth = 2;
#endif

/// One lane of a batched array: entry i is p[i*W]. The generated law blocks
/// index their arguments as H[i], so they run unchanged on a pointer (one
/// element) or on a Lane (one element of a batch).
template <int W, class T>
struct Lane {
  T* p;
  T& operator[](int i) const { return p[i * W]; }
};

/// The first Size entries of a Lane, into a contiguous array.
template <int Size, int W, class T>
inline void copy_lane(Lane<W, T> values, double* copy) {
  for (int i = 0; i < Size; ++i) copy[i] = values[i];
}

/// polar_rotation and rotation_inverse for H given as a Lane: on a contiguous copy.
template <int D, int W, class T>
inline void polar_rotation(Lane<W, T> H, double* R) {
  double copy[D * D];
  copy_lane<D * D>(H, copy);
  polar_rotation<D>(copy, R);
}

template <int D, int W, class T>
inline void rotation_inverse(Lane<W, T> H, const double* R, double* Y) {
  double copy[D * D];
  copy_lane<D * D>(H, copy);
  rotation_inverse<D>(copy, R, Y);
}

/// displacement_gradient on a batch: u is D*N by W, GT D*N by W, H D*D by W.
template <int W, int D, int N>
inline void displacement_gradient_batch(const double* __restrict__ u, const double* __restrict__ GT,
                                        double* __restrict__ H) {
  TENSORMASS_SIMD_LOOP
  for (int l = 0; l < W; ++l)
    for (int a = 0; a < D; ++a)
      for (int c = 0; c < D; ++c) {
        double sum = 0.0;
        for (int j = 0; j < N; ++j) sum += u[(j * D + a) * W + l] * GT[(c * N + j) * W + l];
        H[(a * D + c) * W + l] = sum;
      }
}

/// accumulate_gradient on a batch: g[(j*D+a)*W + l] += sum_c wP[a*D+c] GT[c*N+j],
/// with wP D*D by W and g D*N by W (node-major).
template <int W, int D, int N>
inline void accumulate_gradient_batch(const double* __restrict__ wP, const double* __restrict__ GT,
                                      double* __restrict__ g) {
  TENSORMASS_SIMD_LOOP
  for (int l = 0; l < W; ++l)
    for (int j = 0; j < N; ++j)
      for (int a = 0; a < D; ++a) {
        double sum = g[(j * D + a) * W + l];
        for (int c = 0; c < D; ++c) sum += wP[(a * D + c) * W + l] * GT[(c * N + j) * W + l];
        g[(j * D + a) * W + l] = sum;
      }
}

/// accumulate_hessian on a batch: per component pair (a <= b) the N by N block
/// K_ab += G^T wA_ab G, stored pair by pair as component_pairs<D>*N*N by W.
template <int W, int D, int N>
inline void accumulate_hessian_batch(const double* __restrict__ wA, const double* __restrict__ GT,
                                     double* __restrict__ K_by_pair) {
  constexpr int D2 = D * D;
  int pair = 0;
  for (int a = 0; a < D; ++a)
    for (int b = a; b < D; ++b, ++pair) {
      alignas(64) double Z[D * N * W];  // Z[c][k] = sum_e wA[(a*D+c)][(b*D+e)] GT[e][k]
      TENSORMASS_SIMD_LOOP
      for (int l = 0; l < W; ++l)
        for (int c = 0; c < D; ++c)
          for (int k = 0; k < N; ++k) {
            double sum = 0.0;
            for (int e = 0; e < D; ++e) sum += wA[((a * D + c) * D2 + b * D + e) * W + l] * GT[(e * N + k) * W + l];
            Z[(c * N + k) * W + l] = sum;
          }
      double* __restrict__ block = K_by_pair + pair * N * N * W;
      TENSORMASS_SIMD_LOOP
      for (int l = 0; l < W; ++l)
        for (int j = 0; j < N; ++j)
          for (int k = 0; k < N; ++k) {
            double sum = 0.0;
            for (int c = 0; c < D; ++c) sum += GT[(c * N + j) * W + l] * Z[(c * N + k) * W + l];
            block[(j * N + k) * W + l] += sum;
          }
    }
}

/// scatter_gradient on a batch: element l's gradient to gradient + l*D*N
/// (element by element, ready for the assembler's scatter) from g (D*N by W).
template <int W, int D, int N>
inline void scatter_gradient_batch(const double* __restrict__ g, double* __restrict__ gradient) {
  for (int l = 0; l < W; ++l)
    for (int i = 0; i < D * N; ++i) gradient[l * D * N + i] = g[i * W + l];
}

/// scatter_hessian on a batch: element l's dofs by dofs Hessian (row-major)
/// to hessian + l*dofs*dofs, from the pair blocks.
template <int W, int D, int N>
inline void scatter_hessian_batch(const double* __restrict__ K_by_pair, double* __restrict__ hessian) {
  constexpr int dofs = D * N;
  int pair = 0;
  for (int a = 0; a < D; ++a)
    for (int b = a; b < D; ++b, ++pair)
      for (int j = 0; j < N; ++j)
        for (int k = 0; k < N; ++k) {
          const double* value = K_by_pair + ((pair * N + j) * N + k) * W;
          const int upper = (j * D + a) * dofs + k * D + b, lower = (k * D + b) * dofs + j * D + a;
          for (int l = 0; l < W; ++l) hessian[l * dofs * dofs + upper] = hessian[l * dofs * dofs + lower] = value[l];
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
