/// \file nodal_pressure.hpp
/// Averaged nodal pressure (the `anp` split; Bonet and Burton 1998, in its
/// variational form): the bulk part U(J) of an anp cell's law is taken off
/// the cell and integrated at the nodes instead,
///
///   W = sum_e [W_e(F_e) - V_e U_e(J_e)] + sum_A sum_{e in A} (V_e / n_e) U_e(J_A),
///   J_A = sum_{e in A} (V_e / n_e) J_e / V_A,   V_A = sum_{e in A} V_e / n_e,
///
/// with W_e the cell's kernel energy (the full law), V_e its rest volume,
/// n_e its corner count and A a patch: one node and the anp cells of one
/// material around it. One volume constraint per node instead of one per
/// cell: a tetrahedral mesh has about 5.5 cells per node, so plain tet4
/// meshes lock and these do not.
///
/// With p_A = sum_{e in A} (V_e / n_e) U_e'(J_A) / V_A and p̄_e the mean of
/// p_A over e's corners, the force is element by element,
///   g_e = V_e (p̄_e - U_e'(J_e)) dJ_e/du,
/// and the tangent adds to the cells' element blocks
///   V_e (p̄_e - U_e'(J_e)) d2J_e/du2 - V_e U_e''(J_e) dJ_e/du dJ_e/du^T
/// one rank-one term per patch, coupling every pair of the patch's nodes:
///   (k_A / V_A) w_A w_A^T,   w_A = sum_{e in A} (V_e / n_e) dJ_e/du,
///   k_A = sum_{e in A} (V_e / n_e) U_e''(J_A) / V_A.
/// The tangent is symmetric (W is an energy); its pattern couples the nodes
/// of each patch, two rings of neighbours (make_node_graph adds them).
/// Under a linear law (Hooke) J_e is 1 + tr(eps_e) and d2J_e/du2 = 0.
/// Where |p̄_e| exceeds the cell's modulus, the tangent's p̄_e d2J_e term
/// takes the modulus (with p̄_e's sign) instead: that term is indefinite, and
/// Newton's first iterates near nu = 1/2 reach such pressures (lambda
/// amplifies their linearised volume errors); the tangent is then not the
/// exact derivative there, and is again once the pressure is physical.
///
/// Shapes: u and gradient are dof_count (node-major); the stiffness is the
/// assembler's pattern over the free dofs.
#ifndef TENSORMASS_ASSEMBLY_NODAL_PRESSURE_HPP
#define TENSORMASS_ASSEMBLY_NODAL_PRESSURE_HPP

#include <span>
#include <utility>
#include <vector>

#include "tensormass/assembly/sparse_matrix.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {

class NodalPressure {
 public:
  /// Collects the model's anp cells and their patches (empty() when it has none).
  explicit NodalPressure(const Model& model);
  NodalPressure(Model&&) = delete;  ///< keeps a reference to the model

  bool empty() const { return cells_.empty(); }
  /// Patches, sorted by their node then material: per patch its nodes,
  /// sorted (the tangent couples each pair).
  int patch_count() const { return static_cast<int>(patch_start_.size()) - 1; }
  std::span<const int> patch_nodes(int patch) const {
    return {patch_nodes_.data() + patch_start_[patch],
            static_cast<std::size_t>(patch_start_[patch + 1] - patch_start_[patch])};
  }
  /// The nodal part's energy W - sum_e W_e at u (dof_count).
  double energy(std::span<const double> u) const;
  /// gradient += its force; *stiffness += its tangent when non-null (the
  /// stiffness has the structure of a pattern that couples every patch).
  /// Rows are filled node by node, in parallel: the same bits on any thread count.
  void assemble(std::span<const double> u, std::span<double> gradient, SparseMatrix* stiffness) const;
  /// Whether a patch's tangent changes with u (a non-linear or blending cell in it).
  bool patch_changes(int patch) const;

  /// Doubles of dJ_e/du at most per cell: anp cells have at most 6 nodes in 3D (prism6).
  static constexpr int kCellDofs = 18;

 private:
  /// J_e, dJ_e/du (dofs) and F at each point (points by d by d) of an anp
  /// cell from its local displacements (nodes by dim); J_e is the mean of
  /// the points' J weighted by w_q det J_q (the fbar base's J̄).
  void cell_kinematics(int cell, const double* local, double& J, double* dJ, double* F) const;
  /// d2J_e/du_a du_b (d by d) of anp cell e's nodes a, b at the F of the last evaluation.
  void second_derivative(int e, int a, int b, double* block) const;
  /// U_e, U_e', U_e'' at J for the cell's law (blended while it blends).
  void cell_bulk(int cell, double J, double* out) const;
  /// Whether every cell of the patch has the same U (kernel, blend and derived parameters).
  bool uniform_patch(int patch) const;
  /// uniform_ brought up to date with the model's laws and constants.
  void update_uniform_patches() const;
  /// Per cell J_e, dJ_e, F_e, U_e(J_e) and its derivatives; per patch J_A, p_A, k_A.
  void evaluate(std::span<const double> u) const;
  /// The pattern's positions of the patch's node pairs (built at the first tangent).
  void build_positions(const SparseMatrix& stiffness) const;
  /// stiffness += block (d by d) at the patch's local node pair (a, b), its free rows and columns.
  void add_block(SparseMatrix& stiffness, int patch, int a, int b, const double* block) const;
  /// Node `node`'s rows: its force and, when non-null, its rows of the tangent.
  void assemble_node(int node, std::span<double> gradient, SparseMatrix* stiffness) const;
  int corners(int e) const { return corner_start_[e + 1] - corner_start_[e]; }
  /// dJ_e/du of anp cell e (its nodes by dim) in dJ_, cells packed one after the other.
  double* cell_dJ(int e) const { return &dJ_[static_cast<std::size_t>(corner_start_[e]) * model_->dim()]; }

  const Model* model_;
  std::vector<int> cells_;             ///< the anp cells
  std::vector<double> rest_volume_;    ///< per anp cell, V_e
  std::vector<int> corner_start_;      ///< anp cells+1, into corner_patch_
  std::vector<int> point_start_;       ///< anp cells+1: the cells' quadrature points, into F_ (9 each)
  std::vector<int> corner_patch_;      ///< per anp cell and corner (its node order), the corner's patch
  std::vector<int> patch_start_;       ///< patches+1, into patch_nodes_
  std::vector<int> patch_nodes_;       ///< nodes of each patch, sorted
  std::vector<int> patch_node_;        ///< the node of each patch
  std::vector<double> patch_volume_;   ///< V_A
  std::vector<int> patch_cell_start_;  ///< patches+1, into patch_cells_ (one (patch, cell) pair each)
  std::vector<int> patch_cells_;       ///< per pair, the anp cell
  std::vector<int> pair_corner_;       ///< per pair, the cell's corner at the patch's node
  std::vector<int> pair_local_;        ///< per pair, the cell's nodes' indices in the patch (corners(e) each)
  std::vector<int> pair_local_start_;  ///< pairs+1, into pair_local_
  std::vector<int> node_patch_start_;  ///< nodes+1: the patches holding each node, in node_patches_
  std::vector<int> node_patches_;      ///< per (node, patch holding it): the patch
  std::vector<int> node_patch_local_;  ///< per (node, patch holding it): the node's index in the patch
  std::vector<int> node_first_patch_;  ///< nodes+1: the patches of each node (consecutive)
  mutable std::vector<int>
      pair_position_;  ///< per patch |nodes|^2: (first free row of a, first free column of b) in values, or -1
  mutable std::vector<std::size_t> pair_start_;   ///< patches+1
  mutable std::vector<int> full_row_length_;      ///< per node: its rows' length when all its dofs are free, else 0
  mutable std::vector<int> positions_row_start_;  ///< the row_start the positions were built for
  // Scratch of one evaluation (assemble and energy are not re-entrant, as the assembler).
  mutable std::vector<double> J_, dJ_, F_, U_, dU_, d2U_, coefficient_;
  mutable std::vector<double> geometric_;  ///< per cell, the d2J_e coefficient of the tangent (the pressure capped)
  mutable std::vector<double> JA_, pA_, kA_, w_;            ///< per patch; w_ per patch node and component
  mutable std::vector<char> uniform_;                       ///< per patch, uniform_patch() as of uniform_revision_
  mutable std::pair<long, long> uniform_revision_{-1, -1};  ///< (law, consts) revisions of the model
};

}  // namespace tensormass

#endif
