#pragma once
/// \file inversion_check.hpp
/// Whether a cell is inverted, for one reference element: det(F) at the
/// kernel's quadrature points (from its precomputed rest gradients) and the
/// determinant of the deformed map x(xi) at the element's corners (from the
/// corner shape gradients of tm_element_info). A quadratic or multilinear
/// cell can fold at a corner while every quadrature point stays positive.

#include "tensormass/kernels/kernel_abi.h"

namespace tensormass {

class InversionCheck {
 public:
  explicit InversionCheck(const tm_element_info& element);

  /// True when det(I + grad u) <= 0 (or NaN) at a quadrature point. u: nodes
  /// by dim; consts: the kernel's precomputed constants, whose first
  /// `derived` values are parameters, then per point a weight and the
  /// physical gradients (dim by nodes).
  bool at_quadrature_points(const double* u, const double* consts, int derived, int points) const;

  /// False for an element whose shape gradients are constant (simplices of
  /// order 1): there the quadrature check says everything.
  bool checks_corners() const { return checks_corners_; }

  /// The first corner where det(dx/dxi) <= 0 (or NaN), or -1. x: the
  /// positions of the cell's nodes, nodes by dim (rest, or rest + u).
  int first_flat_corner(const double* x) const;

 private:
  using PointCheck = bool (*)(const double*, const double*, int, int, int);
  using CornerCheck = int (*)(const double*, const double*, int, int);

  const tm_element_info* element_;
  PointCheck at_points_;
  CornerCheck at_corners_;
  bool checks_corners_;
};

}  // namespace tensormass
