/// \file kernel_support.hpp
/// Small fixed-size loops shared by generated kernels (the law-specific code
/// is generated; these contractions are the same for every law). D = dim,
/// N = nodes; GT is the d by n transposed shape-gradient block of one point.
#ifndef TENSORMASS_KERNEL_SUPPORT_HPP
#define TENSORMASS_KERNEL_SUPPORT_HPP

#include <algorithm>
#include <cmath>

#include "tensormass/kernels/kernel_abi.h"
#include "tensormass/kernels/polar_decomposition.hpp"

// Loops over the nodes are marked for vectorisation: with -fopenmp-simd (set
// by the build with TENSORMASS_SIMD) GCC vectorises them as loops instead of
// unrolling them into shuffles, 3x faster at 8 nodes.
#if defined(TENSORMASS_SIMD) || defined(_OPENMP)
#define TENSORMASS_SIMD_LOOP _Pragma("omp simd")
#else
#define TENSORMASS_SIMD_LOOP
#endif

// log and exp with glibc's vector variants (libmvec), as <math.h> declares
// them under -ffast-math: a SIMD loop over a batch's lanes then takes the log
// (or exp) of all of them in one call instead of one scalar call per lane
// (neo-Hookean's batched kernels; the roots J^(-1/3) of the isochoric
// invariants, printed as exp(-log(J)/3)). Set by the build (with
// -fno-math-errno and libmvec) for the kernels only; libmvec's log and exp
// are within 4 ulp. Clang has no such attribute (its lanes call them one by one).
#if defined(TENSORMASS_VECTOR_MATH) && !defined(__clang__)
extern "C" double log(double) noexcept __attribute__((simd("notinbranch")));
extern "C" double exp(double) noexcept __attribute__((simd("notinbranch")));
#endif

// The law blocks a batch's SIMD loop calls (law_weighted_stress, law_tangent
// of batched kernels): always inlined, since a block left out of line runs
// lane by lane, its exp and log calls scalar.
#if defined(__GNUC__)
#define TENSORMASS_LANE_INLINE __attribute__((always_inline)) inline
#else
#define TENSORMASS_LANE_INLINE inline
#endif

namespace tensormass::kernel {

/// precompute's parameter check (kernel_abi.h): TM_PRECOMPUTE_PARAM_COUNT when
/// param_count is not P, TM_PRECOMPUTE_BAD_PARAM - p for the first parameter
/// p that is not finite or outside limits[p], else 0.
template <int P>
inline int check_parameters(const double* params, int param_count, const tm_param_limit (&limits)[P]) {
  if (param_count != P) return TM_PRECOMPUTE_PARAM_COUNT;
  for (int p = 0; p < P; ++p) {
    const double value = params[p];
    const tm_param_limit& limit = limits[p];
    const bool above = limit.lower_inclusive ? value >= limit.lower : value > limit.lower;
    const bool below = limit.upper_inclusive ? value <= limit.upper : value < limit.upper;
    if (!std::isfinite(value) || !above || !below) return TM_PRECOMPUTE_BAD_PARAM - p;
  }
  return 0;
}

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

/// A Lane of H whose polar rotation the batch computed beforehand
/// (polar_rotation_batch): the law block's polar_rotation call reads it, so
/// the SIMD loop over the lanes holds no data-dependent iteration.
template <int W, class T>
struct RotatedLane {
  T* p;
  const double* rotation;  ///< this lane's R: entry i at rotation[i*W]
  T& operator[](int i) const { return p[i * W]; }
};

template <int D, int W, class T>
inline void polar_rotation(RotatedLane<W, T> H, double* R) {
  for (int i = 0; i < D * D; ++i) R[i] = H.rotation[i * W];
}

template <int D, int W, class T>
inline void rotation_inverse(RotatedLane<W, T> H, const double* R, double* Y) {
  rotation_inverse<D>(Lane<W, T>{H.p}, R, Y);
}

/// R (D*D by W): the rotations of F = I + H for a batch's W lanes (H D*D by
/// W). 2D: the closed form, lane by lane. 3D: the Newton-Schulz iteration
/// X <- X (3 I - X^T X) / 2 from X = F on every lane at once, until every
/// lane moved less than 1e-8 in a step (the error left is about the square
/// of that, below rounding; a converged lane stays put). It has no division
/// or root, so a step is a few dependent FMAs where polar_rotation<3>'s
/// Newton step waits on a division and a cube root; it converges when F's
/// singular values lie in (0, sqrt 3), in about 4 to 8 steps for strains
/// of 5 to 50 %. Batches with a lane still moving after kSteps steps (a stretch
/// past 70 %, a singular F, NaN) are done again lane by lane by
/// polar_rotation<3>. Each lane's R is the one polar_rotation<D> gives it
/// alone, to rounding.
template <int D, int W>
inline void polar_rotation_batch(const double* __restrict__ H, double* __restrict__ R) {
  if constexpr (D == 2) {
    TENSORMASS_SIMD_LOOP
    for (int l = 0; l < W; ++l) {
      const double a = 2.0 + H[0 * W + l] + H[3 * W + l], b = H[2 * W + l] - H[1 * W + l];
      const double norm = std::sqrt(a * a + b * b);
      const double c = norm > 0.0 ? a / norm : 1.0, s = norm > 0.0 ? b / norm : 0.0;
      R[0 * W + l] = c;
      R[1 * W + l] = -s;
      R[2 * W + l] = s;
      R[3 * W + l] = c;
    }
  } else {
    static_assert(D == 3, "polar_rotation_batch: 2D or 3D");
    constexpr int kSteps = 12;
    TENSORMASS_SIMD_LOOP
    for (int l = 0; l < W; ++l) {
      // X = F / s, which has F's rotation: s^2 = b / 2 bounds X's largest
      // squared singular value by 2 when F's, at most the largest absolute
      // row sum b of F^T F, could pass 2.5.
      double F[9];
      for (int i = 0; i < 9; ++i) F[i] = H[i * W + l] + (i % 4 == 0 ? 1.0 : 0.0);
      double bound = 0.0;
      for (int i = 0; i < 3; ++i) {
        double row = 0.0;
        for (int j = 0; j < 3; ++j) row += std::abs(F[i] * F[j] + F[3 + i] * F[3 + j] + F[6 + i] * F[6 + j]);
        bound = std::max(bound, row);
      }
      const double scale = bound > 2.5 ? std::sqrt(2.0 / bound) : 1.0;
      for (int i = 0; i < 9; ++i) R[i * W + l] = scale * F[i];
    }
    bool converged = false;
    for (int step = 0; step < kSteps && !converged; ++step) {
      double moved[W];
      TENSORMASS_SIMD_LOOP
      for (int l = 0; l < W; ++l) {
        double X[9];
        for (int i = 0; i < 9; ++i) X[i] = R[i * W + l];
        // B = (3 I - X^T X) / 2, symmetric; written out so that the lanes' loop has no inner loop left.
        const auto column_dot = [&X](int i, int j) { return X[i] * X[j] + X[3 + i] * X[3 + j] + X[6 + i] * X[6 + j]; };
        const double b00 = 1.5 - 0.5 * column_dot(0, 0), b11 = 1.5 - 0.5 * column_dot(1, 1);
        const double b22 = 1.5 - 0.5 * column_dot(2, 2), b01 = -0.5 * column_dot(0, 1);
        const double b02 = -0.5 * column_dot(0, 2), b12 = -0.5 * column_dot(1, 2);
        const double B[9] = {b00, b01, b02, b01, b11, b12, b02, b12, b22};
        // How far X^T X is from I (|2 (I - B)|, summed) and how far the step moves X: both below
        // 1e-8 once converged (a singular X also stops moving, at X^T X != I).
        double change = std::abs(2.0 - 2.0 * b00) + std::abs(2.0 - 2.0 * b11) + std::abs(2.0 - 2.0 * b22) +
                        4.0 * (std::abs(b01) + std::abs(b02) + std::abs(b12));
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            const double next = X[i * 3] * B[j] + X[i * 3 + 1] * B[3 + j] + X[i * 3 + 2] * B[6 + j];
            change = std::max(change, std::abs(next - X[i * 3 + j]));
            R[(i * 3 + j) * W + l] = next;
          }
        moved[l] = change;
      }
      converged = true;
      for (int l = 0; l < W; ++l) converged = converged && moved[l] < 1e-8;  // false on NaN
    }
    if (converged) return;
    for (int l = 0; l < W; ++l) {
      double copy[9], rotation[9];
      copy_lane<9>(Lane<W, const double>{H + l}, copy);
      polar_rotation<3>(copy, rotation);
      for (int i = 0; i < 9; ++i) R[i * W + l] = rotation[i];
    }
  }
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
