/// \file psd_projection.hpp
/// Projection of a symmetric element Hessian onto the positive
/// semi-definite cone: negative eigenvalues are set to zero, the
/// eigenvectors kept. A tangent assembled from projected element Hessians
/// is positive semi-definite (definite once constraints remove the rigid
/// motions), so every Newton step is a descent direction even where the
/// material is unstable (compressed StVK, near-inverted elements); the
/// price is an eigen-decomposition per cell and slower (no longer
/// quadratic) convergence where the projection changed something.
#ifndef TENSORMASS_ASSEMBLY_PSD_PROJECTION_HPP
#define TENSORMASS_ASSEMBLY_PSD_PROJECTION_HPP

namespace tensormass {

/// Replaces the symmetric n x n row-major matrix `hessian` by its closest
/// positive semi-definite matrix in the Frobenius norm (negative eigenvalues
/// clamped to 0). Returns true when some eigenvalue was negative (the
/// matrix changed), false when it is left exactly as it was.
bool project_to_positive_semidefinite(double* hessian, int n);

}  // namespace tensormass

#endif
