/// \file zz_indicator.hpp
/// R_ZZ, the Zienkiewicz-Zhu recovered-stress error indicator per cell, and
/// the cells a threshold on it selects for refinement.
///
/// Stress measure: the symmetric part s = (P + P^T) / 2 of the first
/// Piola-Kirchhoff stress P that the cell's kernel gives at each quadrature
/// point (tm_kernel::stress; a blending cell gives w P_new + (1 - w) P_old,
/// as its forces do). For Hooke it is the Cauchy stress; for the other laws
/// it is a good stress measure for small to moderate strains and rotations
/// only (P is not symmetric under large rotations).
///
/// Recovery, with V_e = sum_q w_q det(J_q) the rest volume of cell e (the
/// weights stored in its constants, kernel_abi.h):
///   s_bar_e  = (1 / V_e) sum_q w_q det(J_q) s_h(q)       cell average
///   s*_i     = sum_{e at i} V_e s_bar_e / sum_{e at i} V_e nodal average
///              over the cells e around node i (every node of the cell,
///              mid-edge nodes of second-order cells included)
///   s*(q)    = sum_j N_j(q) s*_j                          interpolated by
///              the element's shape functions at its default rule
///              (tm_element_info::shape_values)
///
/// Indicator of cell e, an energy norm:
///   R_ZZ(e) = sqrt( sum_q w_q det(J_q) (s* - s_h) : C^-1 : (s* - s_h) )
/// with the isotropic compliance of the small-strain Lame parameters lam, mu
/// of the cell's material (MaterialLaws::lame):
///   s : C^-1 : s = (1 / (2 mu)) ( s : s - lam / (d lam + 2 mu) tr(s)^2 )
/// d = 3 in 3D. In 2D (plane strain, unit thickness) s is the in-plane 2x2
/// stress and d = 2: the inverse of the plane-strain law s = lam tr(e) I +
/// 2 mu e on 2x2 strains, so that s : C^-1 : s = s : e is twice the
/// plane-strain energy density (sigma_zz does no work as e_zz = 0). The unit
/// of R_ZZ is sqrt(energy): sqrt(J) in 3D, sqrt(J/m) in 2D.
///
/// A displacement that is linear in the rest coordinates gives a constant
/// stress: s* = s_h and R_ZZ = 0 up to round-off, on any mesh.
///
/// Cost: one pass over the cells for the nodal averages and one for the
/// indicator (each runs the cell's stress kernel), one over the nodes; no
/// heap allocation per cell, and none at all when a ZzIndicator is reused
/// on models of the same size.
#ifndef TENSORMASS_ADAPTIVITY_ZZ_INDICATOR_HPP
#define TENSORMASS_ADAPTIVITY_ZZ_INDICATOR_HPP

#include <span>
#include <vector>

#include "tensormass/model/model.hpp"

namespace tensormass {

/// Stress components stored per node: 3 in 2D (xx, yy, xy), 6 in 3D
/// (xx, yy, zz, yz, xz, xy).
constexpr int zz_stress_components(int dim) { return dim == 2 ? 3 : 6; }

/// Computes R_ZZ; keeps its nodal storage between calls.
class ZzIndicator {
 public:
  /// R_ZZ of every cell of `model` at displacement `u` (dof_count) into
  /// `indicator` (cell_count, mesh-wide cell order). Throws InputError when
  /// a size does not match, and std::logic_error when a cell's kernel does
  /// not fit its element (other quadrature points or nodes, no lam and mu).
  void compute(const Model& model, std::span<const double> u, std::span<double> indicator);
  /// After compute: the recovered stress s*_i of every node, node_count by
  /// zz_stress_components(dim) (0 at a node no cell uses).
  std::span<const double> nodal_stress() const { return nodal_stress_; }

 private:
  std::vector<double> nodal_stress_;
  std::vector<double> nodal_volume_;
};

/// R_ZZ of every cell (a ZzIndicator used once).
std::vector<double> zz_indicator(const Model& model, std::span<const double> u);

/// The cells (indices into `indicator`, increasing) whose indicator is at
/// least threshold times the largest one; none when every indicator is 0.
/// A threshold of 0 selects every cell (when one is positive), 1 the largest.
/// Throws InputError for a threshold outside [0, 1] (or NaN) and for a
/// negative or non-finite indicator, naming the cell.
std::vector<int> select_cells_at_threshold(std::span<const double> indicator, double threshold);

}  // namespace tensormass

#endif
