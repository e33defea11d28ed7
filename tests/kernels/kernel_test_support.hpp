/// \file kernel_test_support.hpp
/// Shared helpers of the kernel tests: the registry's kernels as test
/// parameters, reproducible distorted rest shapes, parameters and
/// displacements, finite differences, relative errors and small dense
/// linear algebra (3 by 3 matrices, a Gaussian elimination).
#ifndef TENSORMASS_TESTS_KERNEL_TEST_SUPPORT_HPP
#define TENSORMASS_TESTS_KERNEL_TEST_SUPPORT_HPP

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <ostream>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "tensormass/kernels/kernel_abi.h"
#include "tensormass/kernels/registry.hpp"

namespace tmtest {

using Vector = std::vector<double>;

inline const tensormass::Registry& registry() { return tensormass::Registry::instance(); }

// --- Test parameters --------------------------------------------------------

/// "law_element_split", the name of a parameterized test instance.
inline std::string kernel_name(const tm_kernel& kernel) {
  return std::string(kernel.law) + "_" + kernel.element + "_" + kernel.split;
}

/// The registry's kernels for which `keep` holds, in registry order.
inline std::vector<const tm_kernel*> kernels_where(const std::function<bool(const tm_kernel&)>& keep) {
  std::vector<const tm_kernel*> result;
  for (const tm_kernel* kernel : registry().kernels())
    if (keep(*kernel)) result.push_back(kernel);
  return result;
}

inline std::vector<const tm_kernel*> all_kernels() {
  return kernels_where([](const tm_kernel&) { return true; });
}

struct KernelParamName {
  std::string operator()(const testing::TestParamInfo<const tm_kernel*>& info) const {
    return kernel_name(*info.param);
  }
};

/// A (law, element) pair of the registry, whose splits must agree.
struct LawElement {
  std::string law;
  std::string element;
};

inline std::vector<LawElement> law_element_pairs() {
  std::set<std::pair<std::string, std::string>> seen;
  std::vector<LawElement> result;
  for (const tm_kernel* kernel : registry().kernels())
    if (seen.emplace(kernel->law, kernel->element).second) result.push_back({kernel->law, kernel->element});
  return result;
}

inline void PrintTo(const LawElement& pair, std::ostream* os) { *os << pair.law << "/" << pair.element; }

struct LawElementParamName {
  std::string operator()(const testing::TestParamInfo<LawElement>& info) const {
    return info.param.law + "_" + info.param.element;
  }
};

inline std::vector<std::string> element_names() {
  std::vector<std::string> result;
  for (const tm_element_info* info : registry().elements()) result.push_back(info->name);
  return result;
}

struct ElementParamName {
  std::string operator()(const testing::TestParamInfo<std::string>& info) const { return info.param; }
};

inline const tm_element_info& element_of(const tm_kernel& kernel) {
  const tm_element_info* info = registry().element(kernel.element);
  if (info == nullptr) throw std::logic_error(std::string("no element info for ") + kernel.element);
  return *info;
}

/// The reference volume of an element (elements/*.toml reference_volume).
inline double reference_volume(const std::string& element) {
  const tm_element_info* info = registry().element(element);
  if (info == nullptr) throw std::logic_error("unknown element " + element);
  return info->reference_volume;
}

// --- Errors -------------------------------------------------------------------

inline double max_abs(const Vector& values) {
  double result = 0.0;
  for (double value : values) result = std::max(result, std::abs(value));
  return result;
}

inline double max_abs_difference(const Vector& a, const Vector& b) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  double result = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double difference = std::abs(a[i] - b[i]);
    if (!(difference <= result)) result = std::isnan(difference) ? std::numeric_limits<double>::infinity() : difference;
  }
  return result;
}

/// max |a - b| over max(max |a|, max |b|): the error relative to the
/// magnitude of the quantity (0 when both are exactly zero).
inline double relative_error(const Vector& actual, const Vector& expected) {
  const double scale = std::max(max_abs(actual), max_abs(expected));
  const double difference = max_abs_difference(actual, expected);
  if (difference == 0.0) return 0.0;
  return scale > 0.0 ? difference / scale : std::numeric_limits<double>::infinity();
}

inline double relative_error(double actual, double expected) {
  return relative_error(Vector{actual}, Vector{expected});
}

// --- Small dense 3 by 3 algebra (row-major d by d, d = 2 or 3) -----------

using Matrix3 = std::array<double, 9>;

inline Matrix3 identity3() { return {1, 0, 0, 0, 1, 0, 0, 0, 1}; }

inline Matrix3 multiply(const Matrix3& a, const Matrix3& b) {
  Matrix3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[i * 3 + j] += a[i * 3 + k] * b[k * 3 + j];
  return c;
}

inline Matrix3 transpose(const Matrix3& a) {
  Matrix3 t{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t[i * 3 + j] = a[j * 3 + i];
  return t;
}

inline double determinant(const Matrix3& a) {
  return a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) + a[2] * (a[3] * a[7] - a[4] * a[6]);
}

inline Matrix3 inverse(const Matrix3& a) {
  const double det = determinant(a);
  Matrix3 inv{};
  inv[0] = (a[4] * a[8] - a[5] * a[7]) / det;
  inv[1] = (a[2] * a[7] - a[1] * a[8]) / det;
  inv[2] = (a[1] * a[5] - a[2] * a[4]) / det;
  inv[3] = (a[5] * a[6] - a[3] * a[8]) / det;
  inv[4] = (a[0] * a[8] - a[2] * a[6]) / det;
  inv[5] = (a[2] * a[3] - a[0] * a[5]) / det;
  inv[6] = (a[3] * a[7] - a[4] * a[6]) / det;
  inv[7] = (a[1] * a[6] - a[0] * a[7]) / det;
  inv[8] = (a[0] * a[4] - a[1] * a[3]) / det;
  return inv;
}

/// The rotation by `angle` about the axis (x, y, z) (normalised here).
inline Matrix3 rotation(double x, double y, double z, double angle) {
  const double norm = std::sqrt(x * x + y * y + z * z);
  x /= norm;
  y /= norm;
  z /= norm;
  const double c = std::cos(angle), s = std::sin(angle), t = 1.0 - c;
  return {t * x * x + c,     t * x * y - s * z, t * x * z + s * y,  //
          t * x * y + s * z, t * y * y + c,     t * y * z - s * x,  //
          t * x * z - s * y, t * y * z + s * x, t * z * z + c};
}

/// The leading d by d block of a 3 by 3 matrix, row-major (d*d values).
inline Vector block(const Matrix3& a, int dim) {
  Vector result(static_cast<std::size_t>(dim * dim));
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) result[static_cast<std::size_t>(i * dim + j)] = a[i * 3 + j];
  return result;
}

/// A matrix that is the identity outside the leading d by d block.
inline Matrix3 embed(const Matrix3& a, int dim) {
  if (dim == 3) return a;
  Matrix3 result = identity3();
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) result[i * 3 + j] = a[i * 3 + j];
  return result;
}

// --- Reproducible elements ----------------------------------------------

/// An element of one kernel, ready to evaluate: a distorted rest shape, its
/// parameters and the constants `precompute` filled in.
struct Element {
  const tm_kernel* kernel = nullptr;
  Vector rest;    ///< nodes by dim
  Vector params;  ///< the law's parameters (material)
  Vector consts;
  double size = 0.0;  ///< the element's characteristic length (metres)
  int status = -1;    ///< precompute's return value
};

/// Whether the kernel's law takes Young's modulus and Poisson's ratio (and
/// so linearises to Hooke's law with them).
inline bool has_elastic_parameters(const tm_kernel& kernel) {
  return kernel.params == 2 && std::string(kernel.param_names[0]) == "young" &&
         std::string(kernel.param_names[1]) == "poisson";
}

/// Random parameters of the kernel's law: soft tissue to rubber (young
/// 10^4 to 10^6 Pa, poisson 0.3 to 0.45) for laws with those; else each
/// parameter of order one (the laws' other parameters include dimensionless
/// exponents and locking stretches, whose scale the checks' relative
/// tolerances do not need): inside a two-sided limit, 0.5 to 5.5 times the
/// bound's size (at least 1) past a one-sided one, 0.5 to 5.5 without one.
inline Vector material(const tm_kernel& kernel, std::mt19937_64& random) {
  std::uniform_real_distribution<double> exponent(4.0, 6.0), unit(0.0, 1.0);
  if (has_elastic_parameters(kernel)) {
    std::uniform_real_distribution<double> poisson(0.3, 0.45);
    const double young = std::pow(10.0, exponent(random));
    return {young, poisson(random)};
  }
  Vector params;
  for (int p = 0; p < kernel.params; ++p) {
    const tm_param_limit& limit = kernel.param_limits[p];
    const bool low = std::isfinite(limit.lower), high = std::isfinite(limit.upper);
    const double t = unit(random), step = 0.5 + 5.0 * t;
    if (low && high) params.push_back(limit.lower + (0.05 + 0.9 * t) * (limit.upper - limit.lower));
    else if (low) params.push_back(limit.lower + std::max(1.0, std::abs(limit.lower)) * step);
    else if (high) params.push_back(limit.upper - std::max(1.0, std::abs(limit.upper)) * step);
    else params.push_back(step);
  }
  return params;
}

/// A stress scale of the element (Pa): its largest rest stiffness entry
/// over size^(dim - 2), as the modulus of a material of that stiffness.
inline double stress_scale(const Vector& rest_hessian, double size, int dim) {
  double largest = 0.0;
  for (double k : rest_hessian) largest = std::max(largest, std::abs(k));
  return largest * std::pow(size, 2 - dim);
}

/// lam and mu of young and poisson (laws with has_elastic_parameters).
inline std::pair<double, double> lame(const Vector& params) {
  const double young = params[0], poisson = params[1];
  return {young * poisson / ((1 + poisson) * (1 - 2 * poisson)), young / (2 * (1 + poisson))};
}

/// The reference nodes of `info` through the map X = b + s/2 M y(n(r)):
/// n(r) = 2 (r - c)/e maps the reference element (extent e, centre c) into
/// [-1, 1]^d, y(n) = n + 0.06 n_b n_c (3D) or n + 0.06 n_b^2 (2D) is a mild
/// non-affine perturbation (Jacobian I + at most 0.12 off the diagonal,
/// positive everywhere), M a random rotation times a random perturbation of
/// the identity (entries of at most 0.2, hence det(M) > 0), s the size in
/// [1, 10] cm (log-uniform) and b a random offset. `affine` leaves out the non-affine part; `matrix`
/// (if given) receives s/e M, the affine part.
inline Vector rest_shape(const tm_element_info& info, std::mt19937_64& random, double* size_out = nullptr,
                         bool affine = false, Matrix3* matrix = nullptr) {
  const int dim = info.dim, nodes = info.nodes;
  std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-2.0, -1.0);
  const double size = std::pow(10.0, exponent(random));
  double low[3] = {1e300, 1e300, 1e300}, high[3] = {-1e300, -1e300, -1e300};
  for (int j = 0; j < nodes; ++j)
    for (int a = 0; a < dim; ++a) {
      low[a] = std::min(low[a], info.reference_nodes[j * dim + a]);
      high[a] = std::max(high[a], info.reference_nodes[j * dim + a]);
    }
  double extent = 0.0, centre[3] = {0, 0, 0};
  for (int a = 0; a < dim; ++a) {
    extent = std::max(extent, high[a] - low[a]);
    centre[a] = 0.5 * (low[a] + high[a]);
  }
  Matrix3 perturbation = identity3();
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) perturbation[i * 3 + j] += 0.2 * unit(random);
  const Matrix3 turn = dim == 3 ? rotation(unit(random), unit(random), unit(random), 3.0 * unit(random))
                                : rotation(0.0, 0.0, 1.0, 3.0 * unit(random));
  const Matrix3 map = multiply(turn, embed(perturbation, dim));
  double offset[3];
  for (double& b : offset) b = size * unit(random);
  Vector rest(static_cast<std::size_t>(nodes * dim));
  for (int j = 0; j < nodes; ++j) {
    double r[3] = {0, 0, 0}, y[3] = {0, 0, 0};
    for (int a = 0; a < dim; ++a) r[a] = 2.0 * (info.reference_nodes[j * dim + a] - centre[a]) / extent;
    for (int a = 0; a < dim; ++a) {
      y[a] = r[a];
      if (!affine) y[a] += dim == 3 ? 0.06 * r[(a + 1) % 3] * r[(a + 2) % 3] : 0.06 * r[(a + 1) % 2] * r[(a + 1) % 2];
    }
    for (int a = 0; a < dim; ++a) {
      double x = offset[a];
      for (int c = 0; c < dim; ++c) x += 0.5 * size * map[a * 3 + c] * y[c];
      rest[static_cast<std::size_t>(j * dim + a)] = x;
    }
  }
  if (matrix != nullptr) {
    *matrix = map;  // dX/dr = s/e M (in 2D the third row and column are those of I)
    for (int a = 0; a < dim; ++a)
      for (int c = 0; c < dim; ++c) (*matrix)[a * 3 + c] *= size / extent;
  }
  if (size_out != nullptr) *size_out = size;
  return rest;
}

/// An element of `kernel` from the seed: rest shape, material, precompute.
inline Element make_element(const tm_kernel& kernel, std::uint64_t seed, bool affine = false) {
  std::mt19937_64 random(seed);
  Element element;
  element.kernel = &kernel;
  element.rest = rest_shape(element_of(kernel), random, &element.size, affine);
  element.params = material(kernel, random);
  element.consts.assign(static_cast<std::size_t>(kernel.consts), 0.0);
  element.status = kernel.precompute(element.rest.data(), element.params.data(), kernel.params, element.consts.data());
  return element;
}

/// u_j = (G - I) X_j + noise: a random homogeneous deformation with
/// displacement gradient entries up to `strain` plus random nodal noise of
/// `noise` times the element size (strains of a few per cent).
inline Vector random_displacement(const Element& element, std::uint64_t seed, double strain = 0.05,
                                  double noise = 0.01) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const int dim = element.kernel->dim, nodes = element.kernel->nodes;
  double H[9];
  for (double& h : H) h = strain * unit(random);
  Vector u(element.rest.size());
  for (int j = 0; j < nodes; ++j)
    for (int a = 0; a < dim; ++a) {
      double value = noise * element.size * unit(random);
      for (int c = 0; c < dim; ++c) value += H[a * 3 + c] * element.rest[static_cast<std::size_t>(j * dim + c)];
      u[static_cast<std::size_t>(j * dim + a)] = value;
    }
  return u;
}

/// u_j = (F - I) X_j for a 3 by 3 F (its leading d by d block in 2D).
inline Vector homogeneous_displacement(const Element& element, const Matrix3& F) {
  const int dim = element.kernel->dim, nodes = element.kernel->nodes;
  Vector u(element.rest.size());
  for (int j = 0; j < nodes; ++j)
    for (int a = 0; a < dim; ++a) {
      double value = 0.0;
      for (int c = 0; c < dim; ++c)
        value += (F[a * 3 + c] - (a == c ? 1.0 : 0.0)) * element.rest[static_cast<std::size_t>(j * dim + c)];
      u[static_cast<std::size_t>(j * dim + a)] = value;
    }
  return u;
}

// --- Kernel evaluation ----------------------------------------------------

inline double energy(const Element& e, const Vector& u) { return e.kernel->energy(u.data(), e.consts.data()); }

inline Vector gradient(const Element& e, const Vector& u) {
  Vector g(static_cast<std::size_t>(e.kernel->dofs), std::numeric_limits<double>::quiet_NaN());
  e.kernel->gradient(u.data(), e.consts.data(), g.data());
  return g;
}

inline Vector hessian(const Element& e, const Vector& u) {
  const auto dofs = static_cast<std::size_t>(e.kernel->dofs);
  Vector K(dofs * dofs, std::numeric_limits<double>::quiet_NaN());
  e.kernel->hessian(u.data(), e.consts.data(), K.data());
  return K;
}

inline Vector stress(const Element& e, const Vector& u) {
  const auto size = static_cast<std::size_t>(e.kernel->quadrature_points * e.kernel->dim * e.kernel->dim);
  Vector P(size, std::numeric_limits<double>::quiet_NaN());
  e.kernel->stress(u.data(), e.consts.data(), P.data());
  return P;
}

/// Central difference of the energy: dW/du_i ~ (W(u + h e_i) - W(u - h e_i)) / 2h.
inline Vector fd_gradient(const Element& e, const Vector& u, double h) {
  Vector g(u.size());
  Vector shifted = u;
  for (std::size_t i = 0; i < u.size(); ++i) {
    shifted[i] = u[i] + h;
    const double plus = energy(e, shifted);
    shifted[i] = u[i] - h;
    const double minus = energy(e, shifted);
    shifted[i] = u[i];
    g[i] = (plus - minus) / (2 * h);
  }
  return g;
}

/// Central difference of the gradient, column by column (row-major result).
inline Vector fd_hessian(const Element& e, const Vector& u, double h) {
  const std::size_t dofs = u.size();
  Vector K(dofs * dofs);
  Vector shifted = u;
  for (std::size_t j = 0; j < dofs; ++j) {
    shifted[j] = u[j] + h;
    const Vector plus = gradient(e, shifted);
    shifted[j] = u[j] - h;
    const Vector minus = gradient(e, shifted);
    shifted[j] = u[j];
    for (std::size_t i = 0; i < dofs; ++i) K[i * dofs + j] = (plus[i] - minus[i]) / (2 * h);
  }
  return K;
}

/// Richardson extrapolation of a central difference D(h) (error c h^2 + O(h^4)):
/// (4 D(h/2) - D(h)) / 3.
inline Vector richardson(const Vector& coarse, const Vector& fine) {
  Vector result(coarse.size());
  for (std::size_t i = 0; i < coarse.size(); ++i) result[i] = (4.0 * fine[i] - coarse[i]) / 3.0;
  return result;
}

// --- Dense solve ----------------------------------------------------------

/// Solves A x = b (A n by n row-major, copied) by Gaussian elimination with
/// partial pivoting.
inline Vector solve_dense(Vector A, Vector b) {
  const std::size_t n = b.size();
  for (std::size_t k = 0; k < n; ++k) {
    std::size_t pivot = k;
    for (std::size_t i = k + 1; i < n; ++i)
      if (std::abs(A[i * n + k]) > std::abs(A[pivot * n + k])) pivot = i;
    if (A[pivot * n + k] == 0.0) throw std::runtime_error("solve_dense: singular matrix");
    if (pivot != k) {
      for (std::size_t j = 0; j < n; ++j) std::swap(A[k * n + j], A[pivot * n + j]);
      std::swap(b[k], b[pivot]);
    }
    for (std::size_t i = k + 1; i < n; ++i) {
      const double factor = A[i * n + k] / A[k * n + k];
      if (factor == 0.0) continue;
      for (std::size_t j = k; j < n; ++j) A[i * n + j] -= factor * A[k * n + j];
      b[i] -= factor * b[k];
    }
  }
  Vector x(n);
  for (std::size_t k = n; k-- > 0;) {
    double sum = b[k];
    for (std::size_t j = k + 1; j < n; ++j) sum -= A[k * n + j] * x[j];
    x[k] = sum / A[k * n + k];
  }
  return x;
}

}  // namespace tmtest

/// Test parameters print as law/element/split (found by argument-dependent
/// lookup: tm_kernel is in the global namespace).
inline void PrintTo(const tm_kernel* kernel, std::ostream* os) {
  *os << kernel->law << "/" << kernel->element << "/" << kernel->split;
}

#endif
