// Model: lumped masses, consistent loads and constraints.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>

#include "tensormass/common/errors.hpp"
#include "tensormass/mesh/mesh_topology.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {

double Model::cell_energy_scale(int cell) const {
  const tm_kernel& kernel = *kernels_[cell];
  const int n = static_cast<int>(cell_nodes(cell).size());
  double volume = 0.0;
  for (int q = 0; q < kernel.quadrature_points; ++q) volume += consts(cell)[kernel.derived_params + q * (1 + dim_ * n)];
  return cell_modulus(cell) * volume;
}

void Model::complete_partial_sums(const std::function<void(std::span<double>)>& complete_dofs, double energy_scale) {
  complete_dofs(lumped_mass_);
  complete_dofs(gravity_load_);
  energy_scale_ = energy_scale;
}

namespace {

/// The group a validated spec names (std::invalid_argument for an unvalidated one).
const Group& model_group(const Mesh& mesh, const std::string& name) {
  const Group* group = mesh.group(name);
  if (!group)
    throw std::invalid_argument("Model: no group '" + name + "' (validate the specification against the mesh first)");
  return *group;
}

}  // namespace

void Model::compute_masses_and_gravity(const ModelSpec& spec) {
  const int n_dofs = dof_count();
  lumped_mass_.assign(n_dofs, 0.0);
  gravity_load_.assign(n_dofs, 0.0);
  for (const ElementBlock& block : mesh_->blocks) {
    const tm_element_info& element = *block.element;
    const int n = element.nodes;
    for (int local = 0; local < block.count(); ++local) {
      const int cell = block.first_cell + local;
      const tm_kernel& kernel = *kernels_[cell];
      if (kernel.quadrature_points != element.quadrature_points)
        throw std::logic_error(std::string("kernel and element rules differ for ") + element.name);
      const double density = spec.materials[cell_material_[cell]].density;
      // integral of N_i and of N_i^2 over the element, with its own rule.
      std::array<double, kMaxCellNodes> integral_n{}, integral_n2{};
      double volume = 0.0;
      for (int q = 0; q < kernel.quadrature_points; ++q) {
        const double w_det = consts(cell)[kernel.derived_params + q * (1 + dim_ * n)];
        volume += w_det;
        for (int j = 0; j < n; ++j) {
          const double N = element.shape_values[q * n + j];
          integral_n[j] += w_det * N;
          integral_n2[j] += w_det * N * N;
        }
      }
      energy_scale_ += cell_modulus(cell) * volume;
      double diagonal_sum = 0.0;
      for (int j = 0; j < n; ++j) diagonal_sum += integral_n2[j];
      const auto nodes = cell_nodes(cell);
      for (int j = 0; j < n; ++j) {
        // Row sum for linear elements; HRZ (diagonal scaled to the element's
        // mass) for quadratic ones, whose row sums are zero or negative at corners.
        const double mass =
            element.order == 1 ? density * integral_n[j] : density * volume * integral_n2[j] / diagonal_sum;
        if (!(mass > 0.0))
          throw InputError(mesh_->source + ": " + mesh_->describe_cell(cell) + " gets a non-positive lumped mass");
        for (int a = 0; a < dim_; ++a) {
          const std::size_t dof = static_cast<std::size_t>(nodes[j]) * dim_ + a;
          lumped_mass_[dof] += mass;
          gravity_load_[dof] += density * integral_n[j] * spec.loads.gravity[a];
        }
      }
    }
  }
}

namespace {

/// A facet's quadrature rule with its shape functions: weights (points),
/// values (points by nodes) and the two parametric derivatives (points by
/// nodes by 2; the second is 0 on a line).
struct FacetQuadrature {
  int nodes = 0;
  std::vector<double> weights, values, gradients;
  int points() const { return static_cast<int>(weights.size()); }
};

/// A line2 or line3 facet of a 2D mesh (nodes: end, end, middle) with 2 or
/// 3 Gauss points on [-1, 1].
FacetQuadrature line_quadrature(int nodes) {
  const double p2 = 1.0 / std::sqrt(3.0), p3 = std::sqrt(0.6);
  const std::vector<double> points = nodes == 2 ? std::vector<double>{-p2, p2} : std::vector<double>{-p3, 0.0, p3};
  FacetQuadrature rule;
  rule.nodes = nodes;
  rule.weights = nodes == 2 ? std::vector<double>{1.0, 1.0} : std::vector<double>{5.0 / 9, 8.0 / 9, 5.0 / 9};
  for (double r : points) {
    const std::vector<double> N = nodes == 2 ? std::vector<double>{(1 - r) / 2, (1 + r) / 2}
                                             : std::vector<double>{r * (r - 1) / 2, r * (r + 1) / 2, 1 - r * r};
    const std::vector<double> dN =
        nodes == 2 ? std::vector<double>{-0.5, 0.5} : std::vector<double>{r - 0.5, r + 0.5, -2 * r};
    rule.values.insert(rule.values.end(), N.begin(), N.end());
    for (double d : dN) rule.gradients.insert(rule.gradients.end(), {d, 0.0});
  }
  return rule;
}

/// A face of a 3D mesh: the default rule and shape functions of the
/// registry's 2D element with its node count (the element files list face
/// nodes in that element's order).
FacetQuadrature face_quadrature(const tm_element_info& element) {
  FacetQuadrature rule;
  rule.nodes = element.nodes;
  const std::size_t points = element.quadrature_points, n = element.nodes;
  rule.weights.assign(element.weights, element.weights + points);
  rule.values.assign(element.shape_values, element.shape_values + points * n);
  rule.gradients.assign(element.shape_gradients, element.shape_gradients + points * n * 2);
  return rule;
}

FacetQuadrature facet_quadrature(int dim, int nodes) {
  return dim == 2 ? line_quadrature(nodes) : face_quadrature(*facet_element(nodes));
}

}  // namespace

void Model::apply_nodal_forces_and_pressure(const ModelSpec& spec) {
  surface_load_.assign(dof_count(), 0.0);
  for (const NodalForceSpec& load : spec.loads.nodal_forces) {
    const Group& group = model_group(*mesh_, load.region);
    for (int node : group.nodes)
      for (int a = 0; a < dim_; ++a) surface_load_[static_cast<std::size_t>(node) * dim_ + a] += load.force[a];
  }
  if (spec.loads.pressures.empty()) return;
  // node -> cells, to orient each facet's normal away from its cell.
  const std::vector<std::vector<int>> node_cells = cells_around_nodes(*mesh_);
  for (const PressureSpec& load : spec.loads.pressures) {
    const Group& group = model_group(*mesh_, load.region);
    const FacetSet& facets = group.facets;
    for (int f = 0; f < facets.count(); ++f) {
      const int* nodes = facets.nodes.data() + facets.offsets[f];
      const int count = facets.offsets[f + 1] - facets.offsets[f];
      const int owner = facet_owner(*mesh_, node_cells, {nodes, static_cast<std::size_t>(count)});
      if (!is_load_facet(dim_, count) || owner < 0)
        throw std::invalid_argument("Model: pressure on group '" + load.region + "': facet " + std::to_string(f) +
                                    " is not a face of any cell (validate the specification against the mesh first)");
      const int corners = facet_corners(dim_, count);
      std::array<double, 3> cell_centre{}, facet_centre{};
      const auto cn = cell_nodes(owner);
      for (int node : cn)
        for (int a = 0; a < 3; ++a) cell_centre[a] += mesh_->rest_positions[3 * node + a] / cn.size();
      for (int c = 0; c < corners; ++c)
        for (int a = 0; a < 3; ++a) facet_centre[a] += mesh_->rest_positions[3 * nodes[c] + a] / corners;
      const FacetQuadrature rule = facet_quadrature(dim_, count);
      std::array<double, 3> total{};
      std::vector<std::array<double, 3>> nodal(count, std::array<double, 3>{});
      for (int q = 0; q < rule.points(); ++q) {
        const double* N = rule.values.data() + static_cast<std::size_t>(q) * count;
        const double* dN = rule.gradients.data() + static_cast<std::size_t>(q) * count * 2;
        std::array<double, 3> tr{}, ts{};
        for (int j = 0; j < count; ++j)
          for (int a = 0; a < 3; ++a) {
            tr[a] += dN[2 * j] * mesh_->rest_positions[3 * nodes[j] + a];
            ts[a] += dN[2 * j + 1] * mesh_->rest_positions[3 * nodes[j] + a];
          }
        // Area-weighted normal: tr x ts in 3D, tr x z in 2D (unit thickness).
        std::array<double, 3> normal =
            dim_ == 2 ? std::array<double, 3>{tr[1], -tr[0], 0.0}
                      : std::array<double, 3>{tr[1] * ts[2] - tr[2] * ts[1], tr[2] * ts[0] - tr[0] * ts[2],
                                              tr[0] * ts[1] - tr[1] * ts[0]};
        for (int j = 0; j < count; ++j)
          for (int a = 0; a < 3; ++a) nodal[j][a] += rule.weights[q] * N[j] * normal[a];
        for (int a = 0; a < 3; ++a) total[a] += rule.weights[q] * normal[a];
      }
      double outward = 0.0;
      for (int a = 0; a < 3; ++a) outward += total[a] * (facet_centre[a] - cell_centre[a]);
      const double sign = outward >= 0 ? -load.pressure : load.pressure;  // positive pressure pushes inward
      for (int j = 0; j < count; ++j)
        for (int a = 0; a < dim_; ++a)
          surface_load_[static_cast<std::size_t>(nodes[j]) * dim_ + a] += sign * nodal[j][a];
    }
  }
}

namespace {

/// The unit axis (z in 2D) and the angle in radians (std::invalid_argument for a zero axis).
PrescribedRotation prepared_rotation(const RotationSpec& spec, int dim) {
  std::array<double, 3> axis = dim == 2 ? std::array<double, 3>{0.0, 0.0, 1.0} : spec.axis;
  const double length = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  if (!(length > 0)) throw std::invalid_argument("Model: a prescribed rotation with a zero axis");
  for (double& a : axis) a /= length;
  const double sign = dim == 2 && spec.axis[2] < 0 ? -1.0 : 1.0;  // 2D: the axis given as -z turns the other way
  return {axis, spec.centre, sign * spec.angle * M_PI / 180.0};
}

}  // namespace

std::array<double, 3> PrescribedRotation::displacement(const double* x, double fraction) const {
  // Rodrigues: R v = v cos t + (k x v) sin t + k (k.v)(1 - cos t), v = x - centre.
  const double t = fraction * radians, c = std::cos(t), s = std::sin(t);
  const std::array<double, 3> v = {x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]};
  const std::array<double, 3> k = axis;
  const std::array<double, 3> kxv = {k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0]};
  const double kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
  std::array<double, 3> u;
  for (int a = 0; a < 3; ++a) u[a] = v[a] * c + kxv[a] * s + k[a] * kv * (1 - c) - v[a];
  return u;
}

void Model::collect_constraints(const ModelSpec& spec) {
  std::map<int, PrescribedDof> by_dof;  // a later constraint on a dof wins
  profiles_.push_back(TimeProfile{});   // 0: constant, for fixed groups
  for (const std::string& region : spec.fixed)
    for (int node : model_group(*mesh_, region).nodes)
      for (int a = 0; a < dim_; ++a) by_dof[node * dim_ + a] = {node * dim_ + a, 0.0, 0};
  for (const PrescribedSpec& prescribed : spec.prescribed) {
    profiles_.push_back(prescribed.profile);
    const int profile = static_cast<int>(profiles_.size()) - 1;
    int rotation = -1;
    if (prescribed.rotates) {
      rotations_.push_back(prepared_rotation(prescribed.rotation, dim_));
      rotation = static_cast<int>(rotations_.size()) - 1;
    }
    for (int node : model_group(*mesh_, prescribed.region).nodes)
      for (int a = 0; a < dim_; ++a)
        if (prescribed.components[a] || prescribed.rotates)
          by_dof[node * dim_ + a] = {node * dim_ + a, prescribed.displacement[a], profile, rotation};
  }
  for (const auto& [dof, p] : by_dof) prescribed_.push_back(p);
  free_index_.assign(dof_count(), -1);
  for (int dof = 0; dof < dof_count(); ++dof)
    if (!by_dof.count(dof)) {
      free_index_[dof] = static_cast<int>(free_dofs_.size());
      free_dofs_.push_back(dof);
    }
}

void Model::hold(const std::string& group, const std::array<double, 3>& displacement,
                 const std::array<bool, 3>& components) {
  const Group* found = mesh_->group(group);
  if (!found) throw InputError("hold: the mesh has no group '" + group + "'");
  std::vector<PrescribedDof*> held;  // all found before any changes: an error changes nothing
  for (int node : found->nodes)
    for (int a = 0; a < dim_; ++a) {
      if (!components[a]) continue;
      const int dof = node * dim_ + a;
      // prescribed_ is sorted by dof (collect_constraints builds it from a map).
      auto p = std::lower_bound(prescribed_.begin(), prescribed_.end(), dof,
                                [](const PrescribedDof& q, int d) { return q.dof < d; });
      if (p == prescribed_.end() || p->dof != dof)
        throw InputError("hold: node " +
                         std::to_string(mesh_->node_source_ids.empty() ? node : mesh_->node_source_ids[node]) +
                         " of group '" + group + "' has a free component " + std::to_string(a) +
                         " in the scene; only dofs that are fixed or prescribed there can be moved");
      held.push_back(&*p);
    }
  for (PrescribedDof* p : held) *p = PrescribedDof{p->dof, displacement[p->dof % dim_], p->profile, -1, true};
}

}  // namespace tensormass
