/// \file handwritten_stvk.hpp
/// The baseline: St Venant-Kirchhoff element kernels written by hand the way
/// a competent engineer would, in plain loops (total Lagrangian, Voigt B
/// matrix, K = sum_q w det(J) (B^T D B + geometric)), with no symbolic
/// optimisation. Same calling convention as the generated kernels
/// (kernel_abi.h) so that the bench times both through one code path; the
/// constants layout is the baseline's own:
///   consts[0] = lam, consts[1] = mu, then per quadrature point
///   w*det(J) followed by dN_j/dX_c stored node-major (N by 3).
#ifndef TENSORMASS_BENCH_HANDWRITTEN_STVK_HPP
#define TENSORMASS_BENCH_HANDWRITTEN_STVK_HPP

namespace tensormass::bench::handwritten {

constexpr int kTet4Nodes = 4;
constexpr int kTet4Points = 1;
constexpr int kTet4Consts = 2 + kTet4Points * (1 + 3 * kTet4Nodes);
constexpr int kHex8Nodes = 8;
constexpr int kHex8Points = 8;  // 2x2x2 Gauss
constexpr int kHex8Consts = 2 + kHex8Points * (1 + 3 * kHex8Nodes);

/// rest_positions: N by 3, node-major, in the registry's node order (VTK);
/// params: young, poisson. Returns 0, or q+1 for a point with det(J) <= 0.
int stvk_tet4_precompute(const double* rest_positions, const double* params, int param_count, double* consts);
void stvk_tet4_gradient(const double* u, const double* consts, double* gradient);
void stvk_tet4_gradient_hessian(const double* u, const double* consts, double* gradient, double* hessian);

int stvk_hex8_precompute(const double* rest_positions, const double* params, int param_count, double* consts);
void stvk_hex8_gradient(const double* u, const double* consts, double* gradient);
void stvk_hex8_gradient_hessian(const double* u, const double* consts, double* gradient, double* hessian);

/// Flops of the loops above (each multiply and add counted once), per element.
long stvk_flops_gradient(int nodes, int points);
long stvk_flops_gradient_hessian(int nodes, int points);

}  // namespace tensormass::bench::handwritten

#endif
