/// \file polar_decomposition.hpp
/// The rotation of F's polar decomposition F = R S (S symmetric) and the term
/// that gives its derivative, for generated kernels of laws written with R
/// (generator/symbolic.py). H is the displacement gradient, row-major d by d;
/// F = I + H.
#ifndef TENSORMASS_POLAR_DECOMPOSITION_HPP
#define TENSORMASS_POLAR_DECOMPOSITION_HPP

#include <cmath>

namespace tensormass::kernel {

/// R (d by d, row-major): the orthogonal factor of F = I + H. For det F > 0 a
/// rotation; for det F < 0 (an inverted element, 3D) a reflection.
template <int D>
inline void polar_rotation(const double* H, double* R);

/// 2D closed form: R^T F is symmetric when tan(theta) = (F10 - F01) / (F00 + F11).
template <>
inline void polar_rotation<2>(const double* H, double* R) {
  const double a = 2.0 + H[0] + H[3];
  const double b = H[2] - H[1];
  const double norm = std::sqrt(a * a + b * b);
  const double c = norm > 0.0 ? a / norm : 1.0;
  const double s = norm > 0.0 ? b / norm : 0.0;
  R[0] = c;
  R[1] = -s;
  R[2] = s;
  R[3] = c;
}

/// 3D: Higham's Newton iteration X <- (z X + X^-T / z) / 2, quadratically
/// convergent from X = F for any non-singular F. The scale z = |det X|^(-1/3)
/// only speeds up the first steps: once |det X| is within 1 % of 1 the
/// unscaled step (z = 1) converges as fast and saves a cube root per step.
/// Stops once a step moves X by less than 1e-8: the error left after a step
/// is about the square of its size, below rounding. Both measured
/// (random rotations, strains 0.001 to 0.3): 1.5 to 3x faster than scaling
/// every step and stopping at 1e-10, same R to 1e-15.
template <>
inline void polar_rotation<3>(const double* H, double* R) {
  for (int i = 0; i < 9; ++i) R[i] = H[i] + (i % 4 == 0 ? 1.0 : 0.0);
  for (int iteration = 0; iteration < 40; ++iteration) {
    const double c[9] = {R[4] * R[8] - R[5] * R[7], R[5] * R[6] - R[3] * R[8], R[3] * R[7] - R[4] * R[6],
                         R[2] * R[7] - R[1] * R[8], R[0] * R[8] - R[2] * R[6], R[1] * R[6] - R[0] * R[7],
                         R[1] * R[5] - R[2] * R[4], R[2] * R[3] - R[0] * R[5], R[0] * R[4] - R[1] * R[3]};
    const double det = R[0] * c[0] + R[1] * c[1] + R[2] * c[2];
    if (!(std::abs(det) > 0.0) || !std::isfinite(det)) return;  // singular F: no rotation exists
    const double z = std::abs(std::abs(det) - 1.0) > 1e-2 ? 1.0 / std::cbrt(std::abs(det)) : 1.0;
    const double inverse_scale = 1.0 / (det * z);  // X^-T = c / det
    double change = 0.0;
    for (int i = 0; i < 9; ++i) {
      const double next = 0.5 * (z * R[i] + inverse_scale * c[i]);
      change += std::abs(next - R[i]);
      R[i] = next;
    }
    if (change < 1e-8) return;
  }
}

/// Y: in 3D (tr(S) I - S)^-1 (row-major 3 by 3), in 2D 1/tr(S), with
/// S = sym(R^T F). dR = R [omega]x with omega = Y axial(R^T dF - dF^T R).
template <int D>
inline void rotation_inverse(const double* H, const double* R, double* Y);

template <>
inline void rotation_inverse<2>(const double* H, const double* R, double* Y) {
  Y[0] = 1.0 / (R[0] * (1.0 + H[0]) + R[2] * H[2] + R[1] * H[1] + R[3] * (1.0 + H[3]));
}

template <>
inline void rotation_inverse<3>(const double* H, const double* R, double* Y) {
  double S[9];  // R^T F
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double sum = 0.0;
      for (int k = 0; k < 3; ++k) sum += R[k * 3 + i] * (H[k * 3 + j] + (k == j ? 1.0 : 0.0));
      S[i * 3 + j] = sum;
    }
  const double trace = S[0] + S[4] + S[8];
  double M[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) M[i * 3 + j] = (i == j ? trace : 0.0) - 0.5 * (S[i * 3 + j] + S[j * 3 + i]);
  const double c[9] = {M[4] * M[8] - M[5] * M[7], M[5] * M[6] - M[3] * M[8], M[3] * M[7] - M[4] * M[6],
                       M[2] * M[7] - M[1] * M[8], M[0] * M[8] - M[2] * M[6], M[1] * M[6] - M[0] * M[7],
                       M[1] * M[5] - M[2] * M[4], M[2] * M[3] - M[0] * M[5], M[0] * M[4] - M[1] * M[3]};
  const double inverse_det = 1.0 / (M[0] * c[0] + M[1] * c[1] + M[2] * c[2]);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Y[i * 3 + j] = c[j * 3 + i] * inverse_det;  // M^-1 = cof(M)^T / det
}

}  // namespace tensormass::kernel

#endif  // TENSORMASS_POLAR_DECOMPOSITION_HPP
