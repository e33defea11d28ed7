/// \file model.hpp
/// The discrete model: every cell of a mesh bound to a registry kernel (its
/// law from the first matching material region), its constants precomputed
/// once, lumped masses, consistent loads and the constrained degrees of
/// freedom. Degrees of freedom are node-major: dof = node * dim + component.
/// 2D meshes are plane strain with unit thickness.
#ifndef TENSORMASS_MODEL_HPP
#define TENSORMASS_MODEL_HPP

#include <array>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "tensormass/kernels/kernel_abi.h"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/mesh/mesh.hpp"
#include "tensormass/model/material_laws.hpp"
#include "tensormass/model/model_spec.hpp"

namespace tensormass {

/// The split used when a material names none: `whole` for every law and
/// element. (Hooke's `tensor` split, a precomputed Hessian, no longer pays:
/// Hooke cells are folded into a constant matrix and never run a kernel per
/// step, and its 159 constants per tet against 15 made the adaptive
/// criteria, which read the constants of every cell, about 3x slower.)
std::string default_split(const std::string& law, const tm_element_info& element);

/// Index of the first material of `spec` whose region contains mesh-wide
/// cell `cell` ("all" or a group holding it), or -1.
int material_of_cell(const ModelSpec& spec, const Mesh& mesh, int cell);

/// The split a cell of `element` gets under `material`: its own, else
/// default_split; `fbar` on an element without fbar kernels is `whole`.
std::string material_split(const MaterialSpec& material, const tm_element_info& element);

/// The kernel a cell of `element` gets under `material` (at material_split),
/// or nullptr when the registry has none.
const tm_kernel* material_kernel(const MaterialSpec& material, const tm_element_info& element);

/// A displacement imposed on one degree of freedom: amplitude * profile(t),
/// plus the motion of a prescribed rotation when it has one.
struct PrescribedDof {
  int dof;
  double amplitude;
  int profile;        ///< index into Model::profiles
  int rotation = -1;  ///< index into Model::rotations, or -1
  /// Set by Model::hold: the value is `amplitude` from now on, whatever
  /// the time, load factor or profile.
  bool held = false;
};

/// A prescribed rotation, ready to apply: unit axis, centre, full angle in radians.
struct PrescribedRotation {
  std::array<double, 3> axis;
  std::array<double, 3> centre;
  double radians;
  /// The displacement of the point at rest `x` turned by `fraction` of the angle.
  std::array<double, 3> displacement(const double* x, double fraction) const;
};

class Model {
 public:
  /// Binds kernels, precomputes constants and assembles masses and loads.
  /// The spec must have passed validation against this mesh (scene/,
  /// validate_against_mesh); a spec that did not throws std::invalid_argument.
  /// Throws InputError for what only the model computes: a cell with a
  /// non-positive Jacobian or lumped mass at rest, named by element.
  Model(const Mesh& mesh, const ModelSpec& spec);
  /// The model keeps a reference to the mesh: a temporary mesh would dangle.
  Model(Mesh&&, const ModelSpec&) = delete;

  const Mesh& mesh() const { return *mesh_; }
  int dim() const { return dim_; }
  int dof_count() const { return mesh_->node_count() * dim_; }
  int cell_count() const { return static_cast<int>(kernels_.size()); }
  int free_dof_count() const { return static_cast<int>(free_dofs_.size()); }

  /// The nodes of mesh-wide cell `cell`, in kernel order.
  std::span<const int> cell_nodes(int cell) const {
    return {cell_connectivity_.data() + cell_offsets_[cell],
            static_cast<std::size_t>(cell_offsets_[cell + 1] - cell_offsets_[cell])};
  }
  const tm_kernel& kernel(int cell) const { return *kernels_[cell]; }
  const double* consts(int cell) const { return consts_.data() + consts_offsets_[cell]; }
  /// Law index of each cell into `law_names()` (the `law_id` output field).
  int law_id(int cell) const;
  /// Every law of the registry, sorted: law_id -> name.
  const std::vector<std::string>& law_names() const { return law_names_; }
  /// Replaces a cell's kernel by the same element and split under `law`
  /// (O(1) when the constants layout is shared, else recomputed once).
  /// Switching back to the cell's initial law restores its initial kernel
  /// exactly (its constants are never overwritten by a switch).
  /// Throws std::invalid_argument when law_kernel(cell, law) is nullptr.
  void set_law(int cell, const std::string& law);
  /// The kernel set_law(cell, law) would give the cell: its initial kernel
  /// for its initial law, else the same element and split (or `whole`)
  /// whose constants fit the cell's; nullptr when the registry has none.
  const tm_kernel* law_kernel(int cell, const std::string& law) const;
  const tm_kernel& initial_kernel(int cell) const { return *initial_kernels_[cell]; }
  /// Counts the changes of kernels and blends (set_law, start_blend, a blend
  /// ending): what the assembler caches per cell is stale when it moved.
  long law_revision() const { return law_revision_; }
  /// Counts the switches that recomputed a cell's constants (a law with other
  /// derived parameters): a cached K_e of the cell's old kernel is then stale.
  long consts_revision() const { return consts_revision_; }

  /// Smooth law transitions: while a cell blends, its force and stiffness
  /// are w * (current kernel) + (1 - w) * (`from` kernel), on the same
  /// constants. start_blend sets w = 0 (no jump at the switch).
  void start_blend(int cell, const tm_kernel* from);
  /// Sets w; w >= 1 ends the blend.
  void set_blend_weight(int cell, double weight);
  /// The kernel blended from, or nullptr when the cell is not blending.
  const tm_kernel* blend_from(int cell) const { return blend_from_.empty() ? nullptr : blend_from_[cell]; }
  double blend_weight(int cell) const { return blend_from_.empty() ? 1.0 : blend_weight_[cell]; }
  int material(int cell) const { return cell_material_[cell]; }

  /// dof_count(): lumped mass (row sum for first-order, HRZ for quadratic).
  const std::vector<double>& lumped_mass() const { return lumped_mass_; }
  /// dof_count(): consistent body force rho g integral(N_i).
  const std::vector<double>& gravity_load() const { return gravity_load_; }
  /// dof_count(): nodal forces and pressure on the reference configuration.
  const std::vector<double>& surface_load() const { return surface_load_; }
  /// dof_count(): index among the free dofs, or -1 for a constrained dof.
  const std::vector<int>& free_index() const { return free_index_; }
  const std::vector<int>& free_dofs() const { return free_dofs_; }
  const std::vector<PrescribedDof>& prescribed() const { return prescribed_; }
  const std::vector<TimeProfile>& profiles() const { return profiles_; }
  const std::vector<PrescribedRotation>& rotations() const { return rotations_; }
  /// Holds the constrained dofs of `group`'s nodes at `displacement` (per
  /// component) from now on, replacing their profile or rotation: a
  /// boundary condition changed between steps (Python's set_prescribed).
  /// Only the components flagged in `components` change. Throws InputError
  /// when the group is unknown or one of its dofs is free in the scene
  /// (making a free dof constrained would change the linear system's size).
  void hold(const std::string& group, const std::array<double, 3>& displacement,
            const std::array<bool, 3>& components = {true, true, true});
  /// Dynamic solvers: the factor of every load at time t (LoadsSpec::profile).
  double load_factor(double t) const { return load_profile_.factor(t); }

  /// Sets every constrained dof of `u` (dof_count) to its value at time `t`;
  /// the static solver passes the load factor as t with ramp profiles.
  void apply_constraints(double t, std::span<double> u, bool static_load_factor = false) const;
  /// The value apply_constraints gives the prescribed dof `p` at time t.
  double prescribed_value(const PrescribedDof& p, double t, bool static_load_factor = false) const;
  /// Sum over the cells of the small-strain Young's modulus times rest
  /// volume (J, or J/m in 2D): the size of energies whose round-off decides
  /// whether a change of the total energy is meaningful (line searches).
  double energy_scale() const { return energy_scale_; }
  /// The small-strain Young's modulus times rest volume of one cell (its term of energy_scale()).
  double cell_energy_scale(int cell) const;
  /// The small-strain Young's modulus of the cell's material (MaterialLaws::modulus).
  double cell_modulus(int cell) const { return materials_[cell_material_[cell]].modulus(); }
  /// The constants of material `m` bound to the registry's laws.
  const MaterialLaws& material_laws(int m) const { return materials_[m]; }
  int material_count() const { return static_cast<int>(materials_.size()); }
  /// A model of one MPI rank's part of a mesh (Distribution::holds_part)
  /// sums only its cells into the lumped mass, the gravity load and the
  /// energy scale: `complete_dofs` completes the first two from every
  /// rank's part, `energy_scale` is the whole mesh's.
  void complete_partial_sums(const std::function<void(std::span<double>)>& complete_dofs, double energy_scale);
  /// Total strain energy at displacement u (dof_count).
  double strain_energy(std::span<const double> u) const;
  /// First cell whose deformation gradient has det <= 0 (or NaN) at a
  /// quadrature point or whose deformed map has det <= 0 at a corner
  /// (InversionCheck), or -1; cells under an invertible law (tm_kernel::invertible) are skipped.
  int first_inverted_cell(std::span<const double> u) const;
  /// Gathers the cell's displacements (nodes by dim) from u.
  void gather(int cell, std::span<const double> u, double* local) const;

 private:
  void bind_kernels(const ModelSpec& spec);
  void compute_masses_and_gravity(const ModelSpec& spec);
  void apply_nodal_forces_and_pressure(const ModelSpec& spec);
  void collect_constraints(const ModelSpec& spec);
  void precompute(int cell);
  /// The parameters `kernel` takes on `cell` (rest: its node positions):
  /// the material's, with the fibre directions of the cell's centre.
  std::vector<double> cell_parameters(int cell, const tm_kernel& kernel, const double* rest) const;
  /// local (nodes by dim) += the cell's rest positions.
  void add_rest_positions(int cell, double* local) const;

  const Mesh* mesh_;
  int dim_;
  std::vector<int> cell_offsets_;       ///< cell_count()+1
  std::vector<int> cell_connectivity_;  ///< nodes of every cell, concatenated
  std::vector<const tm_kernel*> kernels_, initial_kernels_;
  std::vector<const tm_kernel*> blend_from_;  ///< empty until the first blend
  std::vector<double> blend_weight_;
  std::vector<std::size_t> consts_offsets_;
  std::vector<double> consts_;
  std::vector<int> cell_material_;
  std::vector<MaterialLaws> materials_;  ///< per material of the spec
  std::vector<std::string> law_names_;
  std::vector<double> lumped_mass_, gravity_load_, surface_load_;
  std::vector<int> free_index_, free_dofs_;
  std::vector<PrescribedDof> prescribed_;
  std::vector<TimeProfile> profiles_;
  std::vector<PrescribedRotation> rotations_;
  TimeProfile load_profile_;
  long law_revision_ = 0;
  long consts_revision_ = 0;
  double energy_scale_ = 0;
};

}  // namespace tensormass

#endif
