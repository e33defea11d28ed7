#include "tensormass/assembly/psd_projection.hpp"

// GCC 12 flags Eigen's AVX-512 packet code in the eigen-solver as "may be
// used uninitialized" (a known false positive, GCC bug 105593).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <Eigen/Eigenvalues>

namespace tensormass {

bool project_to_positive_semidefinite(double* hessian, int n) {
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  Eigen::Map<Matrix> H(hessian, n, n);
  const Eigen::SelfAdjointEigenSolver<Matrix> eigen(H);
  const Eigen::VectorXd& values = eigen.eigenvalues();
  if (eigen.info() != Eigen::Success || values.minCoeff() >= 0.0) return false;
  const Eigen::VectorXd clamped = values.cwiseMax(0.0);
  H = eigen.eigenvectors() * clamped.asDiagonal() * eigen.eigenvectors().transpose();
  return true;
}

}  // namespace tensormass
