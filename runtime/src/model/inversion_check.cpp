#include "tensormass/model/inversion_check.hpp"

#include <cmath>

namespace tensormass {

namespace {

template <int D>
double determinant(const double F[D][D]) {
  if constexpr (D == 2) {
    return F[0][0] * F[1][1] - F[0][1] * F[1][0];
  } else {
    return F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1]) - F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0]) +
           F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]);
  }
}

/// D and N fixed so that the loops unroll (this runs every step) for the
/// usual node counts; N = 0 reads the count from `nodes` (any element).
template <int D, int N>
bool inverted_at_a_point(const double* u, const double* consts, int derived, int points, int nodes) {
  const int n = N > 0 ? N : nodes;
  for (int q = 0; q < points; ++q) {
    const double* GT = consts + derived + q * (1 + D * n) + 1;  // dim by nodes
    double F[D][D];
    for (int a = 0; a < D; ++a)
      for (int c = 0; c < D; ++c) {
        double sum = a == c ? 1.0 : 0.0;
        for (int j = 0; j < n; ++j) sum += u[j * D + a] * GT[c * n + j];
        F[a][c] = sum;
      }
    if (!(determinant<D>(F) > 0.0)) return true;
  }
  return false;
}

template <int D, int N>
int flat_corner(const double* x, const double* gradients, int corners, int nodes) {
  const int n = N > 0 ? N : nodes;
  for (int k = 0; k < corners; ++k) {
    const double* G = gradients + k * n * D;  // nodes by dim
    double J[D][D];
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b) {
        double sum = 0.0;
        for (int j = 0; j < n; ++j) sum += x[j * D + a] * G[j * D + b];
        J[a][b] = sum;
      }
    if (!(determinant<D>(J) > 0.0)) return k;
  }
  return -1;
}

template <int D, int N>
void specialised(int nodes, auto& at_points, auto& at_corners) {
  if (N == 0 || nodes == N) {
    at_points = inverted_at_a_point<D, N>;
    at_corners = flat_corner<D, N>;
  }
}

/// The shape gradients are the same at every corner: the map is affine.
bool constant_gradients(const tm_element_info& element) {
  const int size = element.nodes * element.dim;
  for (int k = 1; k < element.corner_count; ++k)
    for (int i = 0; i < size; ++i)
      if (std::abs(element.corner_gradients[k * size + i] - element.corner_gradients[i]) > 1e-12) return false;
  return true;
}

}  // namespace

InversionCheck::InversionCheck(const tm_element_info& element)
    : element_(&element), at_points_(nullptr), at_corners_(nullptr), checks_corners_(!constant_gradients(element)) {
  // Unrolled for the common node counts; any other count takes the N = 0 loops.
  if (element.dim == 2) {
    specialised<2, 0>(element.nodes, at_points_, at_corners_);
    specialised<2, 4>(element.nodes, at_points_, at_corners_);
    specialised<2, 6>(element.nodes, at_points_, at_corners_);
    specialised<2, 8>(element.nodes, at_points_, at_corners_);
  } else {
    specialised<3, 0>(element.nodes, at_points_, at_corners_);
    specialised<3, 4>(element.nodes, at_points_, at_corners_);
    specialised<3, 8>(element.nodes, at_points_, at_corners_);
    specialised<3, 10>(element.nodes, at_points_, at_corners_);
    specialised<3, 20>(element.nodes, at_points_, at_corners_);
  }
}

bool InversionCheck::at_quadrature_points(const double* u, const double* consts, int derived, int points) const {
  return at_points_(u, consts, derived, points, element_->nodes);
}

int InversionCheck::first_flat_corner(const double* x) const {
  return at_corners_(x, element_->corner_gradients, element_->corner_count, element_->nodes);
}

}  // namespace tensormass
