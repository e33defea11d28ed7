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

struct FacetRule {
  std::vector<std::array<double, 2>> points;
  std::vector<double> weights;
};

FacetRule gauss_line(int count) {
  if (count == 2) {
    const double p = 1.0 / std::sqrt(3.0);
    return {{{-p, 0}, {p, 0}}, {1.0, 1.0}};
  }
  const double p = std::sqrt(0.6);
  return {{{-p, 0}, {0, 0}, {p, 0}}, {5.0 / 9, 8.0 / 9, 5.0 / 9}};
}

FacetRule gauss_square(int count) {
  const FacetRule line = gauss_line(count);
  FacetRule rule;
  for (std::size_t i = 0; i < line.points.size(); ++i)
    for (std::size_t j = 0; j < line.points.size(); ++j) {
      rule.points.push_back({line.points[i][0], line.points[j][0]});
      rule.weights.push_back(line.weights[i] * line.weights[j]);
    }
  return rule;
}

FacetRule triangle_rule() {
  return {{{1.0 / 6, 1.0 / 6}, {2.0 / 3, 1.0 / 6}, {1.0 / 6, 2.0 / 3}}, {1.0 / 6, 1.0 / 6, 1.0 / 6}};
}

/// Shape functions and their two parametric derivatives of a facet with
/// `nodes` nodes (line2, line3 in 2D; tri3, quad4, tri6, quad8 in 3D).
void facet_shape(int dim, int nodes, double r, double s, double* N, double (*dN)[2]) {
  if (dim == 2 && nodes == 2) {
    N[0] = (1 - r) / 2, N[1] = (1 + r) / 2;
    dN[0][0] = -0.5, dN[1][0] = 0.5;
  } else if (dim == 2 && nodes == 3) {
    N[0] = r * (r - 1) / 2, N[1] = r * (r + 1) / 2, N[2] = 1 - r * r;
    dN[0][0] = r - 0.5, dN[1][0] = r + 0.5, dN[2][0] = -2 * r;
  } else if (nodes == 3 || nodes == 6) {
    const double L[3] = {1 - r - s, r, s};
    const double dL[3][2] = {{-1, -1}, {1, 0}, {0, 1}};
    if (nodes == 3) {
      for (int i = 0; i < 3; ++i) N[i] = L[i], dN[i][0] = dL[i][0], dN[i][1] = dL[i][1];
    } else {
      for (int i = 0; i < 3; ++i) {
        N[i] = L[i] * (2 * L[i] - 1);
        for (int c = 0; c < 2; ++c) dN[i][c] = (4 * L[i] - 1) * dL[i][c];
        const int k = (i + 1) % 3;
        N[3 + i] = 4 * L[i] * L[k];
        for (int c = 0; c < 2; ++c) dN[3 + i][c] = 4 * (dL[i][c] * L[k] + L[i] * dL[k][c]);
      }
    }
  } else {
    const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int i = 0; i < 4; ++i) {
      const double a = corner[i][0], b = corner[i][1];
      if (nodes == 4) {
        N[i] = (1 + a * r) * (1 + b * s) / 4;
        dN[i][0] = a * (1 + b * s) / 4, dN[i][1] = b * (1 + a * r) / 4;
      } else {
        N[i] = (1 + a * r) * (1 + b * s) * (a * r + b * s - 1) / 4;
        dN[i][0] = a * (1 + b * s) * (2 * a * r + b * s) / 4;
        dN[i][1] = b * (1 + a * r) * (a * r + 2 * b * s) / 4;
      }
    }
    if (nodes == 8) {  // mid-edge nodes 4..7 on edges 0-1, 1-2, 2-3, 3-0
      N[4] = (1 - r * r) * (1 - s) / 2, dN[4][0] = -r * (1 - s), dN[4][1] = -(1 - r * r) / 2;
      N[5] = (1 + r) * (1 - s * s) / 2, dN[5][0] = (1 - s * s) / 2, dN[5][1] = -s * (1 + r);
      N[6] = (1 - r * r) * (1 + s) / 2, dN[6][0] = -r * (1 + s), dN[6][1] = (1 - r * r) / 2;
      N[7] = (1 - r) * (1 - s * s) / 2, dN[7][0] = -(1 - s * s) / 2, dN[7][1] = -s * (1 - r);
    }
  }
}

FacetRule facet_rule(int dim, int nodes) {
  if (dim == 2) return gauss_line(nodes == 2 ? 2 : 3);
  if (nodes == 3 || nodes == 6) return triangle_rule();
  return gauss_square(nodes == 4 ? 2 : 3);
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
      const FacetRule rule = facet_rule(dim_, count);
      std::array<double, 3> total{};
      std::vector<std::array<double, 3>> nodal(count, std::array<double, 3>{});
      for (std::size_t q = 0; q < rule.points.size(); ++q) {
        double N[8], dN[8][2];
        facet_shape(dim_, count, rule.points[q][0], rule.points[q][1], N, dN);
        std::array<double, 3> tr{}, ts{};
        for (int j = 0; j < count; ++j)
          for (int a = 0; a < 3; ++a) {
            tr[a] += dN[j][0] * mesh_->rest_positions[3 * nodes[j] + a];
            ts[a] += dN[j][1] * mesh_->rest_positions[3 * nodes[j] + a];
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
        throw InputError("hold: node " + std::to_string(mesh_->node_source_ids[node]) + " of group '" + group +
                         "' has a free component " + std::to_string(a) +
                         " in the scene; only dofs that are fixed or prescribed there can be moved");
      held.push_back(&*p);
    }
  for (PrescribedDof* p : held) *p = PrescribedDof{p->dof, displacement[p->dof % dim_], p->profile, -1, true};
}

}  // namespace tensormass
