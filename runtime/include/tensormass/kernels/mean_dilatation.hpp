/// \file mean_dilatation.hpp
/// The mean-dilatation (F-bar) formulation of the `fbar` kernels: each point's
/// deformation gradient F_q is replaced by F̄_q = (J̄ / J_q)^(1/d) F_q, where
/// J_q = det F_q and J̄ = Σ_q w_q J_q / Σ_q w_q is the element's volume ratio.
/// The energy Π = Σ_q w_q W(F̄_q) is the law's own, so the formulation works
/// for every law file; the volumetric part of W sees one dilatation per
/// element (no volumetric locking) and the tangent stays symmetric (Π is an
/// energy). In the linear limit it is the B-bar method.
///
/// Derivatives (φ_q(F_q, J̄) = w_q W(F̄_q), P̄ = P(F̄), A = A(F̄), T = F^-T,
/// p = P̄ : F̄, V = A : F̄, a = F̄ : A : F̄, M = P̄ + V, α = (J̄/J)^(1/d),
/// 𝒯_iJkL = T_kJ T_iL, w̃_q = w_q / Σ w):
///   φ_F   = w (α P̄ - p/d T)
///   φ_J̄   = w p / (d J̄)
///   φ_FF  = w (α² A - α/d (M⊗T + T⊗M) + (p + a)/d² T⊗T + p/d 𝒯)
///   φ_FJ̄  = w / (d J̄) (α M - (p + a)/d T)
///   φ_J̄J̄  = w (a + p - d p) / (d² J̄²)
///   ∂J̄/∂F_q = w̃_q J_q T_q,  ∂²J̄/∂F_q² = w̃_q J_q (T⊗T - 𝒯)
/// so, with B_q the point's gradient operator, S1 = Σ φ_J̄ and S2 = Σ φ_J̄J̄:
///   g = Σ_q B_qᵀ (φ_F + S1 w̃ J T)
///   K = Σ_q B_qᵀ (φ_FF + S1 w̃ J (T⊗T - 𝒯)) B_q + c bᵀ + b cᵀ + S2 b bᵀ
///   b = Σ_q B_qᵀ w̃ J T,  c = Σ_q B_qᵀ φ_FJ̄
/// (docs/formulations.md). `Law` supplies the generated law block at one point:
///   Law::energy(H, w, consts) -> w W(I + H)
///   Law::stress(H, consts, P)        P (d by d, row-major)
///   Law::tangent(H, consts, P, A)    P and A = dP/dF (d² by d²)
#ifndef TENSORMASS_MEAN_DILATATION_HPP
#define TENSORMASS_MEAN_DILATATION_HPP

#include <cmath>

#include "tensormass/kernels/kernel_support.hpp"

namespace tensormass::kernel::mean_dilatation {

/// Finite strain: F̄ = (J̄/J)^(1/d) F, the formulas above.
namespace finite_strain {

/// C = cof(F) = det(F) F^-T (D by D, row-major); returns det(F).
template <int D>
inline double cofactor(const double* F, double* C) {
  if constexpr (D == 2) {
    C[0] = F[3];
    C[1] = -F[2];
    C[2] = -F[1];
    C[3] = F[0];
    return F[0] * F[3] - F[1] * F[2];
  } else {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
        C[i * 3 + j] = F[i1 * 3 + j1] * F[i2 * 3 + j2] - F[i1 * 3 + j2] * F[i2 * 3 + j1];
      }
    return F[0] * C[0] + F[1] * C[1] + F[2] * C[2];
  }
}

/// The element's kinematics: per point F, J, T = F^-T, the weight w, α and
/// H̄ = F̄ - I; the element's volume ratio J̄ and reference volume Σ w.
template <int D, int Q>
struct Kinematics {
  double F[Q][D * D];
  double T[Q][D * D];
  double J[Q];
  double w[Q];
  double alpha[Q];
  double Hbar[Q][D * D];
  double volume_ratio;
  double reference_volume;
};

/// Fills `k` from the displacements (N*D) and the per-point constants
/// (`points`: Q blocks of w*det(J) then G^T, as kernel_abi.h lays them out).
template <int D, int N, int Q>
inline void kinematics(const double* u, const double* points, Kinematics<D, Q>& k) {
  double volume = 0.0, current = 0.0;
  for (int q = 0; q < Q; ++q) {
    const double* point = points + q * (1 + D * N);
    displacement_gradient<D, N>(u, point + 1, k.F[q]);
    for (int a = 0; a < D; ++a) k.F[q][a * D + a] += 1.0;
    double C[D * D];
    k.J[q] = cofactor<D>(k.F[q], C);
    for (int i = 0; i < D * D; ++i) k.T[q][i] = C[i] / k.J[q];
    k.w[q] = point[0];
    volume += k.w[q];
    current += k.w[q] * k.J[q];
  }
  k.reference_volume = volume;
  k.volume_ratio = current / volume;
  for (int q = 0; q < Q; ++q) {
    const double ratio = k.volume_ratio / k.J[q];
    k.alpha[q] = D == 3 ? std::cbrt(ratio) : std::sqrt(ratio);
    for (int i = 0; i < D * D; ++i) k.Hbar[q][i] = k.alpha[q] * k.F[q][i];
    for (int a = 0; a < D; ++a) k.Hbar[q][a * D + a] -= 1.0;
  }
}

/// Π = Σ_q w_q W(F̄_q).
template <class Law, int D, int N, int Q>
inline double energy(const double* u, const double* points, const double* consts) {
  Kinematics<D, Q> k;
  kinematics<D, N, Q>(u, points, k);
  double W = 0.0;
  for (int q = 0; q < Q; ++q) W += Law::energy(k.Hbar[q], k.w[q], consts);
  return W;
}

/// P(F̄_q) at every point (Q by D by D): the stress of the formulation.
template <class Law, int D, int N, int Q>
inline void stress(const double* u, const double* points, const double* consts, double* stress) {
  Kinematics<D, Q> k;
  kinematics<D, N, Q>(u, points, k);
  for (int q = 0; q < Q; ++q) Law::stress(k.Hbar[q], consts, stress + q * D * D);
}

/// p = P̄ : F̄ at point q (F̄ = α F).
template <int D, int Q>
inline double stress_power(const Kinematics<D, Q>& k, int q, const double* P) {
  double sum = 0.0;
  for (int i = 0; i < D * D; ++i) sum += P[i] * k.F[q][i];
  return k.alpha[q] * sum;
}

/// The force's integrand at point q: φ_F + S1 w̃ J T (D by D).
template <int D, int Q>
inline void point_force(const Kinematics<D, Q>& k, int q, const double* P, double p, double S1, double* out) {
  const double w = k.w[q], alpha = k.alpha[q];
  const double volumetric = S1 * w / k.reference_volume * k.J[q];
  for (int i = 0; i < D * D; ++i) out[i] = w * (alpha * P[i] - p / D * k.T[q][i]) + volumetric * k.T[q][i];
}

/// g = dΠ/du (N*D, node-major).
template <class Law, int D, int N, int Q>
inline void gradient(const double* u, const double* points, const double* consts, double* gradient) {
  Kinematics<D, Q> k;
  kinematics<D, N, Q>(u, points, k);
  double P[Q][D * D], p[Q], S1 = 0.0;
  for (int q = 0; q < Q; ++q) {
    Law::stress(k.Hbar[q], consts, P[q]);
    p[q] = stress_power(k, q, P[q]);
    S1 += k.w[q] * p[q] / (D * k.volume_ratio);
  }
  double g[D][N] = {};
  for (int q = 0; q < Q; ++q) {
    double force[D * D];
    point_force(k, q, P[q], p[q], S1, force);
    accumulate_gradient<D, N>(force, points + q * (1 + D * N) + 1, g);
  }
  scatter_gradient<D, N>(g, gradient);
}

/// What the tangent needs at one point besides P̄ and A: M = P̄ + A : F̄, p and a.
template <int D>
struct PointTangent {
  double P[D * D];
  double A[D * D * D * D];
  double M[D * D];
  double p;
  double a;
};

template <class Law, int D, int Q>
inline void point_tangent(const Kinematics<D, Q>& k, int q, const double* consts, PointTangent<D>& t) {
  constexpr int D2 = D * D;
  Law::tangent(k.Hbar[q], consts, t.P, t.A);
  const double alpha = k.alpha[q];
  t.p = stress_power(k, q, t.P);
  t.a = 0.0;
  for (int r = 0; r < D2; ++r) {
    double V = 0.0;
    for (int s = 0; s < D2; ++s) V += t.A[r * D2 + s] * alpha * k.F[q][s];
    t.M[r] = t.P[r] + V;
    t.a += alpha * k.F[q][r] * V;
  }
}

/// Overwrites t.A with the point's block of the tangent:
/// φ_FF + S1 w̃ J (T⊗T - 𝒯) (D² by D², row (i*D+J), column (k*D+L)).
template <int D, int Q>
inline void point_block(const Kinematics<D, Q>& k, int q, double S1, PointTangent<D>& t) {
  constexpr int D2 = D * D;
  const double w = k.w[q], alpha = k.alpha[q];
  const double* T = k.T[q];
  const double volumetric = S1 * w / k.reference_volume * k.J[q];
  const double tt = w * (t.p + t.a) / (D * D) + volumetric;  // coefficient of T⊗T
  const double swap = w * t.p / D - volumetric;              // coefficient of 𝒯
  for (int i = 0; i < D; ++i)
    for (int J = 0; J < D; ++J)
      for (int kk = 0; kk < D; ++kk)
        for (int L = 0; L < D; ++L) {
          const int r = i * D + J, s = kk * D + L;
          double& entry = t.A[r * D2 + s];
          entry = w * (alpha * alpha * entry - alpha / D * (t.M[r] * T[s] + T[r] * t.M[s])) + tt * T[r] * T[s] +
                  swap * T[kk * D + J] * T[i * D + L];
        }
}

/// g (when not null) and K = d²Π/du² (N*D by N*D, row-major).
template <class Law, int D, int N, int Q>
inline void gradient_hessian(const double* u, const double* points, const double* consts, double* gradient,
                             double* hessian) {
  constexpr int dofs = D * N;
  Kinematics<D, Q> k;
  kinematics<D, N, Q>(u, points, k);
  PointTangent<D> t[Q];
  double S1 = 0.0, S2 = 0.0;
  const double Jbar = k.volume_ratio;
  for (int q = 0; q < Q; ++q) {
    point_tangent<Law>(k, q, consts, t[q]);
    S1 += k.w[q] * t[q].p / (D * Jbar);
    S2 += k.w[q] * (t[q].a + t[q].p - D * t[q].p) / (D * D * Jbar * Jbar);
  }
  double g[D][N] = {}, b[D][N] = {}, c[D][N] = {};
  double K[component_pairs<D>][N * N] = {};
  for (int q = 0; q < Q; ++q) {
    const double* GT = points + q * (1 + D * N) + 1;
    if (gradient) {
      double force[D * D];
      point_force(k, q, t[q].P, t[q].p, S1, force);
      accumulate_gradient<D, N>(force, GT, g);
    }
    double dJbar[D * D], mixed[D * D];
    const double w = k.w[q], alpha = k.alpha[q];
    for (int i = 0; i < D * D; ++i) {
      dJbar[i] = w / k.reference_volume * k.J[q] * k.T[q][i];
      mixed[i] = w / (D * Jbar) * (alpha * t[q].M[i] - (t[q].p + t[q].a) / D * k.T[q][i]);
    }
    accumulate_gradient<D, N>(dJbar, GT, b);
    accumulate_gradient<D, N>(mixed, GT, c);
    point_block(k, q, S1, t[q]);
    accumulate_hessian<D, N>(t[q].A, GT, K);
  }
  if (gradient) scatter_gradient<D, N>(g, gradient);
  scatter_hessian<D, N>(K, hessian);
  double bv[dofs], cv[dofs];
  scatter_gradient<D, N>(b, bv);
  scatter_gradient<D, N>(c, cv);
  for (int r = 0; r < dofs; ++r)
    for (int s = 0; s < dofs; ++s) hessian[r * dofs + s] += cv[r] * bv[s] + bv[r] * cv[s] + S2 * bv[r] * bv[s];
}

}  // namespace finite_strain

/// Small strain: the laws whose energy is quadratic in H (Hooke, the
/// `linear` flag) get the B-bar method itself, H̄ = H + (θ̄ - θ)/d I with
/// θ = tr H and θ̄ = Σ w θ / Σ w, so that Π stays quadratic in u: F̄'s root
/// of J̄/J would add the finite-strain terms a small-strain law has no use
/// for (it sees a rotation's tr H = 2 (cos a - 1) as a volume change, and
/// near incompressibility λ makes that stiff). With 𝒫 = I - (1/d) I⊗I the
/// deviatoric projector, S = Σ w tr P̄, v = A I, a0 = I:A:I:
///   g = Σ_q B_qᵀ (w 𝒫P̄ + S/d w̃ I)
///   K = Σ_q B_qᵀ w 𝒫A𝒫 B_q + (c bᵀ + b cᵀ)/d + Σ_q w a0/d² b bᵀ,
///   b = Σ_q B_qᵀ w̃ I,  c = Σ_q B_qᵀ w (v - a0/d I)
namespace small_strain {

/// Per point H̄ and w; the reference volume Σ w.
template <int D, int Q>
struct Kinematics {
  double Hbar[Q][D * D];
  double w[Q];
  double reference_volume;
};

template <int D, int N, int Q>
inline void kinematics(const double* u, const double* points, Kinematics<D, Q>& k) {
  double volume = 0.0, dilatation = 0.0, theta[Q];
  for (int q = 0; q < Q; ++q) {
    const double* point = points + q * (1 + D * N);
    displacement_gradient<D, N>(u, point + 1, k.Hbar[q]);
    theta[q] = 0.0;
    for (int a = 0; a < D; ++a) theta[q] += k.Hbar[q][a * D + a];
    k.w[q] = point[0];
    volume += k.w[q];
    dilatation += k.w[q] * theta[q];
  }
  k.reference_volume = volume;
  for (int q = 0; q < Q; ++q)
    for (int a = 0; a < D; ++a) k.Hbar[q][a * D + a] += (dilatation / volume - theta[q]) / D;
}

template <class Law, int D, int N, int Q>
inline double energy(const double* u, const double* points, const double* consts) {
  Kinematics<D, Q> k;
  kinematics<D, N, Q>(u, points, k);
  double W = 0.0;
  for (int q = 0; q < Q; ++q) W += Law::energy(k.Hbar[q], k.w[q], consts);
  return W;
}

template <class Law, int D, int N, int Q>
inline void stress(const double* u, const double* points, const double* consts, double* stress) {
  Kinematics<D, Q> k;
  kinematics<D, N, Q>(u, points, k);
  for (int q = 0; q < Q; ++q) Law::stress(k.Hbar[q], consts, stress + q * D * D);
}

template <int D>
inline double trace(const double* M) {
  double sum = 0.0;
  for (int a = 0; a < D; ++a) sum += M[a * D + a];
  return sum;
}

/// w 𝒫P̄ + S/d w̃ I at point q.
template <int D, int Q>
inline void point_force(const Kinematics<D, Q>& k, int q, const double* P, double S, double* out) {
  const double mean = trace<D>(P) / D;
  for (int i = 0; i < D * D; ++i) out[i] = k.w[q] * P[i];
  for (int a = 0; a < D; ++a) out[a * D + a] += k.w[q] * -mean + S / D * k.w[q] / k.reference_volume;
}

template <class Law, int D, int N, int Q>
inline void gradient(const double* u, const double* points, const double* consts, double* gradient) {
  Kinematics<D, Q> k;
  kinematics<D, N, Q>(u, points, k);
  double P[Q][D * D], S = 0.0;
  for (int q = 0; q < Q; ++q) {
    Law::stress(k.Hbar[q], consts, P[q]);
    S += k.w[q] * trace<D>(P[q]);
  }
  double g[D][N] = {};
  for (int q = 0; q < Q; ++q) {
    double force[D * D];
    point_force(k, q, P[q], S, force);
    accumulate_gradient<D, N>(force, points + q * (1 + D * N) + 1, g);
  }
  scatter_gradient<D, N>(g, gradient);
}

template <class Law, int D, int N, int Q>
inline void gradient_hessian(const double* u, const double* points, const double* consts, double* gradient,
                             double* hessian) {
  constexpr int D2 = D * D, dofs = D * N;
  Kinematics<D, Q> k;
  kinematics<D, N, Q>(u, points, k);
  double P[Q][D2], A[Q][D2 * D2], S = 0.0, S2 = 0.0;
  for (int q = 0; q < Q; ++q) {
    Law::tangent(k.Hbar[q], consts, P[q], A[q]);
    S += k.w[q] * trace<D>(P[q]);
  }
  double g[D][N] = {}, b[D][N] = {}, c[D][N] = {};
  double K[component_pairs<D>][N * N] = {};
  for (int q = 0; q < Q; ++q) {
    const double* GT = points + q * (1 + D * N) + 1;
    if (gradient) {
      double force[D2];
      point_force(k, q, P[q], S, force);
      accumulate_gradient<D, N>(force, GT, g);
    }
    double v[D2] = {}, a0 = 0.0;  // v = A I, a0 = I:A:I
    for (int r = 0; r < D2; ++r)
      for (int a = 0; a < D; ++a) v[r] += A[q][r * D2 + a * D + a];
    for (int a = 0; a < D; ++a) a0 += v[a * D + a];
    double unit[D2] = {}, mixed[D2];
    for (int a = 0; a < D; ++a) unit[a * D + a] = k.w[q] / k.reference_volume;
    for (int r = 0; r < D2; ++r) mixed[r] = k.w[q] * v[r];
    for (int a = 0; a < D; ++a) mixed[a * D + a] -= k.w[q] * a0 / D;
    accumulate_gradient<D, N>(unit, GT, b);
    accumulate_gradient<D, N>(mixed, GT, c);
    S2 += k.w[q] * a0 / (D * D);
    for (int r = 0; r < D2; ++r)  // w 𝒫A𝒫
      for (int s = 0; s < D2; ++s) {
        const double Ir = r % (D + 1) == 0 ? 1.0 : 0.0, Is = s % (D + 1) == 0 ? 1.0 : 0.0;
        double& entry = A[q][r * D2 + s];
        entry = k.w[q] * (entry - (Ir * v[s] + v[r] * Is) / D + Ir * Is * a0 / (D * D));
      }
    accumulate_hessian<D, N>(A[q], GT, K);
  }
  if (gradient) scatter_gradient<D, N>(g, gradient);
  scatter_hessian<D, N>(K, hessian);
  double bv[dofs], cv[dofs];
  scatter_gradient<D, N>(b, bv);
  scatter_gradient<D, N>(c, cv);
  for (int r = 0; r < dofs; ++r)
    for (int s = 0; s < dofs; ++s) hessian[r * dofs + s] += (cv[r] * bv[s] + bv[r] * cv[s]) / D + S2 * bv[r] * bv[s];
}

}  // namespace small_strain

}  // namespace tensormass::kernel::mean_dilatation

#endif
