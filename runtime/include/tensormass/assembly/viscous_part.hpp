/// \file viscous_part.hpp
/// Finite-strain viscoelasticity (Simo 1987; Holzapfel 2000, section 6.10)
/// for the cells whose law has a Prony series (tm_kernel::prony_terms).
/// The law's kernel gives the instantaneous elastic response. At each
/// quadrature point its second Piola-Kirchhoff stress is split into the bulk
/// part's S_U = J U'(J) C^-1 and the rest S_d = S - S_U (the isochoric
/// stress of a law written as isochoric + volumetric; the whole stress of a
/// law with no bulk part), and term i of the series relaxes S_d with the
/// weight g_i and S_U with k_i (0 unless the law declares volumetric
/// weights), both with the time tau_i:
///
///   G(t) = g_inf + sum_i g_i exp(-t / tau_i),   g_inf = 1 - sum_i g_i,
///   S(t) = g_inf S_d + sum_i g_i H_i + k_inf S_U + sum_i k_i B_i,
///   H_i(t) = integral_0^t exp(-(t - s) / tau_i) dS_d/ds ds   (B_i likewise of S_U).
///
/// Over a step of length dt, with e_i = exp(-dt / tau_i) and
/// c_i = (1 - e_i) tau_i / dt (the update is exact when the stresses vary
/// linearly over the step),
///
///   H_i(t + dt) = e_i H_i(t) + c_i (S_d(t + dt) - S_d(t))   (B_i likewise),
///   S(t + dt)   = beta_d S_d + beta_U S_U + S_h,
///   beta_d      = g_inf + sum_i g_i c_i,   beta_U = k_inf + sum_i k_i c_i,
///   S_h         = sum_i g_i (e_i H_i - c_i S_d(t)) + k_i (e_i B_i - c_i S_U(t))   (fixed over the step).
///
/// So a cell's force and tangent are its kernel's, g and K, turned into
///   beta_d g + (beta_U - beta_d) g_U + g_h,   beta_d K + (beta_U - beta_d) K_U + K_h,
/// with g_U, K_U those of the bulk part integrated at the cell's points and
/// g_h, K_h those of the fixed stress S_h (a geometric stiffness); they
/// derive from the step's energy beta_d W + (beta_U - beta_d) W_U +
/// sum_q w_q S_h : E. A static solve has dt = infinity: the long-term
/// response (beta_d = g_inf, beta_U = k_inf).
///
/// The history (H_i, B_i and the stresses at the last commit, at each point
/// of each viscous cell) is the integrators' State::viscous_history, so that
/// checkpoints carry it and a resumed run goes on bit for bit. Cells of the
/// whole split and the one-point anp split (tet4, tri3) only: their
/// kernels' F is the plain deformation gradient at each point.
#ifndef TENSORMASS_ASSEMBLY_VISCOUS_PART_HPP
#define TENSORMASS_ASSEMBLY_VISCOUS_PART_HPP

#include <span>
#include <vector>

#include "tensormass/model/model.hpp"

namespace tensormass {

class ViscousPart {
 public:
  /// Collects the model's cells whose kernel has a Prony series; InputError
  /// naming the material when its weights sum to 1 or more, or when such a
  /// cell runs a split other than whole or the one-point anp.
  explicit ViscousPart(const Model& model);
  ViscousPart(Model&&) = delete;  ///< keeps a reference to the model

  bool empty() const { return cells_.empty(); }
  int cell_count() const { return static_cast<int>(cells_.size()); }
  /// Doubles of State::viscous_history: per viscous cell and point, d-by-d
  /// blocks H_1 .. H_m, then S_d at the last commit; when the bulk part
  /// relaxes, B_1 .. B_m and S_U follow.
  std::size_t history_size() const { return history_start_.empty() ? 0 : history_start_.back(); }
  /// The viscous index of mesh-wide cell `cell`, or -1 for an elastic cell.
  int index_of(int cell) const { return cell_index_.empty() ? -1 : cell_index_[cell]; }

  /// Sets up a step of length dt from `history` (history_size(), or empty:
  /// the reference state). dt = infinity: the long-term (static) response;
  /// dt = 0: the instantaneous one, as before any step.
  void begin_step(std::span<const double> history, double dt);
  /// Turns the kernel's force g (dofs) and Hessian k (dofs by dofs,
  /// row-major, or null) of viscous cell `index` at its local displacements
  /// `u` (nodes by dim) into the step's, in place.
  void adjust(int index, const double* u, double* g, double* k) const;
  /// The step's energy of viscous cell `index` from its kernel's energy W.
  double adjust_energy(int index, const double* u, double W) const;
  /// Ends the step at u (dof_count): history (history_size()) <- its update.
  void commit(std::span<const double> u, std::vector<double>& history) const;

 private:
  struct Cell {
    int cell;
    int series;  ///< its Prony series, into term_start_
  };
  /// adjust, adjust_energy and commit for one cell of dimension D.
  template <int D>
  void adjust_cell(int index, const double* u, double* g, double* k) const;
  template <int D>
  double energy_cell(int index, const double* u, double W) const;
  template <int D>
  void commit_cell(int v, std::span<const double> u, std::vector<double>& history) const;
  /// The index of the series (weights, times), added when new.
  int series_of(const std::vector<double>& weights, const std::vector<double>& times,
                const std::vector<double>& volumetric);
  /// d-by-d history blocks per point of a cell of `series`.
  int blocks_per_point(int series) const;
  /// Per term of each distinct series (cells of one material share theirs):
  /// the weights g_i, k_i and the relaxation time tau_i.
  std::vector<double> weight_, volumetric_weight_, time_;
  std::vector<int> term_start_;           ///< per series +1, into weight_/time_
  std::vector<char> relaxes_bulk_;        ///< per series: some k_i > 0
  std::vector<double> beta_, beta_bulk_;  ///< per series, of the current step: beta_d, beta_U
  std::vector<Cell> cells_;
  std::vector<int> cell_index_;             ///< per mesh cell, or empty
  std::vector<std::size_t> history_start_;  ///< per viscous cell +1
  std::vector<std::size_t> point_start_;    ///< per viscous cell +1, into fixed_stress_
  std::vector<double> fixed_stress_;        ///< S_h, d by d per point
  std::vector<double> decay_, ramp_;        ///< e_i and c_i per term, of the current step
  const Model* model_;
};

}  // namespace tensormass

#endif
