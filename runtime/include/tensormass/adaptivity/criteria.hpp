/// \file criteria.hpp
/// Per-element criteria of the adaptive model (docs/architecture.md; origin report
/// section 5): each predicts, from one element's nodes, whether the linear
/// law errs there. Every criterion is O(nodes of the element).
///
///   R_EL   max over edges |l - l0| / l0 (edge = its two end corners)
///   R_V    |v - v0| / v0, v = sum_q w_q det(J0_q) det(F_q) (area in 2D)
///   R_VL   v / mean_edge^3 (2D: a / mean_edge^2)                       quality
///   R_VLX  6 sqrt(2) v l_harm / mean_edge^4 (1 for a regular tet;
///          2D: (4 / sqrt 3) a l_harm / mean_edge^3, 1 for an equilateral triangle)  quality
///   R_S    |(1/v) sum_q w_q det(J0_q) sum_j N_j(q) f_j|, f_j the internal
///          force at node j assembled over all elements (the origin's F_j,
///          "the force applied at the vertex"; an element's own forces sum
///          to zero); a force (N): the shape-weighted average of the
///          nodal forces over the element
///   R_NL   max over quadrature points of |1/2 H^T H|_F, the quadratic part
///          of the Green-Lagrange strain that the linear law drops (grows
///          with rotation as well as with strain)
///   R_E    max over quadrature points of |E|_F, E = (F^T F - I)/2: the
///          strain without the rotation (0 under any rigid motion), which a
///          corotational law still treats linearly
///   R_P    max over quadrature points of |P_target(F) - P_base(F)|_F / E:
///          the stress the ladder's first law gets wrong against the law the
///          criterion lifts a cell to, in units of Young's modulus E (the
///          generated `stress` kernels of both laws on the cell's constants;
///          E from their first two derived parameters, lam and mu). It weighs
///          strain by what it does to the stress: under compression with
///          nu near 1/2 it picks the cells whose error matters, where R_NL
///          treats every component alike (bench/adaptive_oracle.py: the
///          indentation within 1 % with its top 20 % of the cells, R_NL's top
///          30 %). Not screened (no bound on its change for any law).
///
/// With the ladder [hooke, corotational, rich], R_NL large and R_E small means
/// rotation (corotational suffices); R_E large means strain (the rich law).
///
/// Note on R_S: the forces of ONE element sum to zero (translation
/// invariance), and a tet4/tri3 (or any affine first-order element) weighs
/// its nodes equally, so R_S of the element's own gradient is 0 up to
/// round-off there; pass the nodes' total (assembled) forces, the origin's
/// "force applied at the vertex", for a meaningful value. R_S is +inf when
/// v <= 0; R_VL and R_VLX are negative for an inverted element.
///
/// Quality criteria (R_VL, R_VLX) fail when their value drops BELOW the
/// threshold; the others fail at or above it. Lengths and volumes are measured on
/// the deformed element (rest + u).
#ifndef TENSORMASS_CRITERIA_HPP
#define TENSORMASS_CRITERIA_HPP

#include <cmath>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tensormass/model/model.hpp"
#include "tensormass/parallel/distribution.hpp"

namespace tensormass {

/// What a criterion sees of one element.
struct ElementView {
  const tm_element_info& element;  ///< reference element (edges, weights, shape values)
  const tm_kernel& kernel;         ///< current kernel (its consts layout: see kernel_abi.h)
  const double* consts;            ///< the element's constants
  const double* rest;              ///< nodes by dim rest positions (only when needs_rest())
  const double* u;                 ///< nodes by dim displacements
  const double* force;  ///< nodes by dim assembled internal forces at the element's nodes (only when needs_force())
  int dim;
  double modulus;  ///< small-strain Young's modulus of the cell's material (Model::cell_modulus): a stress scale
};

/// One block of cells to evaluate at once.
struct BlockInput {
  const Model& model;
  const ElementBlock& block;
  std::span<const double> u;       ///< dof_count displacements
  std::span<const double> forces;  ///< dof_count assembled internal forces (read only when needs_force())
  /// Over MPI ranks: only this rank's own cells are evaluated (the others' values are left as they were).
  const Distribution* distribution = nullptr;
  /// cell_count flags, or null: only the cells whose flag is 1 are
  /// evaluated (the others' values are left as they were; CriteriaScreen).
  const unsigned char* selected = nullptr;
};

class Criterion {
 public:
  virtual ~Criterion() = default;
  virtual std::string name() const = 0;
  /// The criterion's value on one element.
  virtual double evaluate(const ElementView& view) const = 0;
  /// values[cell] (mesh-wide index) for every cell of the block: the same
  /// values as evaluate() cell by cell. Called by every thread of an
  /// enclosing parallel region (or outside one, serially), it shares the
  /// cells among them by a static schedule over block.count() with no
  /// barrier at the end (`omp for schedule(static) nowait`), so that a
  /// following loop of the same schedule reads the values its own thread
  /// wrote. The criteria override it with a loop compiled for the block's
  /// element shape (no virtual call or shape dispatch per cell).
  virtual void evaluate_block(const BlockInput& input, std::span<double> values) const;
  /// Quality criteria fail below their threshold, the others above it.
  virtual bool is_quality() const { return false; }
  /// R_S needs the element's internal force.
  virtual bool needs_force() const { return false; }
  /// Criteria on edge lengths read the rest positions; the others only the
  /// constants (quadrature weights and shape gradients) and u.
  virtual bool needs_rest() const { return true; }
  /// Screening (criteria_screen.hpp), for criteria that are functions of the
  /// displacement gradients H_q at the quadrature points alone: an upper
  /// bound on max_q |H_q|_F from the criterion's value; +inf when the value
  /// does not bound it (or the criterion is not such a function).
  virtual double gradient_norm_bound(double /*value*/, int /*dim*/) const {
    return std::numeric_limits<double>::infinity();
  }
  /// The slope a such that, when max_q |H_q|_F <= h and every
  /// |H'_q - H_q|_F <= delta, the value moves by at most a delta + delta^2 / 2;
  /// +inf when the criterion has no such bound (it is then never screened).
  virtual double change_slope(double /*h*/) const { return std::numeric_limits<double>::infinity(); }
  bool screenable() const { return std::isfinite(change_slope(0.0)); }
  /// Quality: value < threshold; others: value >= threshold, so that a
  /// threshold of 0 fails every cell (the pure last rung of the ladder).
  bool fails(double value, double threshold) const { return is_quality() ? value < threshold : value >= threshold; }
};

/// The two laws R_P compares: the ladder's first law and the law the
/// criterion lifts a cell to (defaults: the default ladder [hooke, stvk]).
/// The other criteria do not read them.
struct CriterionLaws {
  std::string base = "hooke";
  std::string target = "stvk";
};

/// The criterion named R_EL, R_V, R_VL, R_VLX, R_S, R_NL, R_E or R_P; throws
/// std::invalid_argument for any other name, and for R_P when the registry
/// has no `whole` stress kernels of both laws on a common element.
std::unique_ptr<Criterion> make_criterion(const std::string& name, const CriterionLaws& laws = {});

/// All names, in the order above.
const std::vector<std::string>& criterion_names();

}  // namespace tensormass

#endif
