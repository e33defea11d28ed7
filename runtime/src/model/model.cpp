#include "tensormass/model/model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/law_parameters.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/model/inversion_check.hpp"

namespace tensormass {

std::string default_split(const std::string&, const tm_element_info&) { return "whole"; }

namespace {

bool group_has_cell(const Group& group, int cell) {
  return std::binary_search(group.cells.begin(), group.cells.end(), cell);
}

}  // namespace

int material_of_cell(const ModelSpec& spec, const Mesh& mesh, int cell) {
  for (std::size_t m = 0; m < spec.materials.size(); ++m) {
    const MaterialSpec& material = spec.materials[m];
    if (material.region == "all") return static_cast<int>(m);
    const Group* group = mesh.group(material.region);
    if (group && group_has_cell(*group, cell)) return static_cast<int>(m);
  }
  return -1;
}

std::string material_split(const MaterialSpec& material, const tm_element_info& element) {
  if (material.split.empty()) return default_split(material.law, element);
  // fbar on a mixed mesh: the elements without fbar kernels keep `whole`
  // (one quadrature point, where the mean dilatation is the point's own, and
  // the quadratic elements and prism6, which it does not free); the locking
  // warning still names the first-order ones.
  const Registry& registry = Registry::instance();
  if (material.split == "fbar" && !registry.find(material.law, element.name, "fbar")) return "whole";
  // anp on a mixed mesh: the one-point elements take the nodal pressure, the
  // others the mean dilatation where they have it (hex8, pyramid5, quad4).
  if (material.split == "anp" && !registry.find(material.law, element.name, "anp"))
    return registry.find(material.law, element.name, "fbar") ? "fbar" : "whole";
  return material.split;
}

const tm_kernel* material_kernel(const MaterialSpec& material, const tm_element_info& element) {
  return Registry::instance().find(material.law, element.name, material_split(material, element));
}

Model::Model(const Mesh& mesh, const ModelSpec& spec) : mesh_(&mesh), dim_(mesh.dim) {
  law_names_ = Registry::instance().laws();
  cell_offsets_.push_back(0);
  for (const ElementBlock& block : mesh.blocks) {
    cell_connectivity_.insert(cell_connectivity_.end(), block.connectivity.begin(), block.connectivity.end());
    for (int local = 0; local < block.count(); ++local)
      cell_offsets_.push_back(cell_offsets_.back() + block.element->nodes);
  }
  load_profile_ = spec.loads.profile;
  bind_kernels(spec);
  compute_masses_and_gravity(spec);
  apply_nodal_forces_and_pressure(spec);
  collect_constraints(spec);
}

void Model::bind_kernels(const ModelSpec& spec) {
  const int cells = mesh_->cell_count();
  kernels_.resize(cells);
  cell_material_.resize(cells);
  consts_offsets_.resize(cells + 1);
  for (std::size_t m = 0; m < spec.materials.size(); ++m) {
    const int line = spec.materials[m].line;
    materials_.emplace_back(spec.materials[m], spec.source + (line > 0 ? ":" + std::to_string(line) : "") +
                                                   ": material " + std::to_string(m));
  }
  std::size_t total = 0;
  for (const ElementBlock& block : mesh_->blocks) {
    for (int local = 0; local < block.count(); ++local) {
      const int cell = block.first_cell + local;
      const int m = material_of_cell(spec, *mesh_, cell);
      const tm_kernel* kernel = m < 0 ? nullptr : material_kernel(spec.materials[m], *block.element);
      if (!kernel)
        throw std::invalid_argument("Model: " + mesh_->describe_cell(cell) +
                                    " has no material or kernel (validate the specification against the mesh first)");
      kernels_[cell] = kernel;
      cell_material_[cell] = m;
      consts_offsets_[cell] = total;
      total += static_cast<std::size_t>(kernel->consts);
    }
  }
  consts_offsets_[cells] = total;
  consts_.assign(total, 0.0);
  for (int cell = 0; cell < cells; ++cell) precompute(cell);
  initial_kernels_ = kernels_;
}

void Model::precompute(int cell) {
  const tm_kernel& kernel = *kernels_[cell];
  double rest[kMaxCellDofs] = {};
  add_rest_positions(cell, rest);
  const MaterialLaws& material = materials_[cell_material_[cell]];
  const std::vector<double> params = cell_parameters(cell, kernel, rest);
  const int status = precompute_checked(kernel, rest, params, consts_.data() + consts_offsets_[cell], material.owner());
  if (status != 0)
    throw InputError(mesh_->source + ": " + mesh_->describe_cell(cell) +
                     " has a non-positive Jacobian at rest (quadrature point " + std::to_string(status - 1) +
                     "): inverted or degenerate element");
  const int corner = InversionCheck(*mesh_->blocks[mesh_->locate(cell).first].element).first_flat_corner(rest);
  if (corner >= 0)
    throw InputError(mesh_->source + ": " + mesh_->describe_cell(cell) + " has a non-positive Jacobian at corner " +
                     std::to_string(corner) + " at rest: inverted or degenerate element");
}

std::vector<double> Model::cell_parameters(int cell, const tm_kernel& kernel, const double* rest) const {
  const MaterialLaws& material = materials_[cell_material_[cell]];
  std::vector<double> params = material.parameters(kernel);
  const int families = fibre_families(kernel);
  if (families == 0) return params;
  FibreField::Vector centre{};
  for (int j = 0; j < kernel.nodes; ++j)
    for (int a = 0; a < dim_; ++a) centre[a] += rest[j * dim_ + a] / kernel.nodes;
  for (int f = 0; f < families; ++f) {
    const FibreField& field = material.fibres()[f];
    if (!field.given())
      throw InputError(material.owner() + ": law " + kernel.law + " reads " +
                       (families == 2 ? "two fibre families" : "a fibre direction") + "; give the material `" +
                       (f == 0 ? "fibres" : "fibres2") + "` (docs/scene.md)");
    const FibreField::Vector a = field.at(centre, mesh_->describe_cell(cell));
    const std::size_t first = static_cast<std::size_t>(kernel.params - 3 * (families - f));
    std::copy(a.begin(), a.end(), params.begin() + static_cast<std::ptrdiff_t>(first));
  }
  return params;
}

int Model::law_id(int cell) const {
  const auto it = std::find(law_names_.begin(), law_names_.end(), kernels_[cell]->law);
  return static_cast<int>(it - law_names_.begin());
}

const tm_kernel* Model::law_kernel(int cell, const std::string& law) const {
  const tm_kernel& current = *kernels_[cell];
  if (law == current.law) return &current;
  if (law == initial_kernels_[cell]->law) return initial_kernels_[cell];
  const Registry& registry = Registry::instance();
  // The tensor split's constants extend the quadrature layout that `whole`
  // reads, so a tensor cell can switch to `whole` of another law in place.
  // An fbar or anp cell keeps its split: `whole` would bring its volumetric
  // locking back (and anp's patches are fixed for the assembler's life).
  const tm_kernel* next = registry.find(law, current.element, current.split);
  if ((!next || next->consts > current.consts) && !locking_free_split(current))
    next = registry.find(law, current.element, "whole");
  const std::size_t slot = consts_offsets_[cell + 1] - consts_offsets_[cell];
  return next && static_cast<std::size_t>(next->consts) <= slot ? next : nullptr;
}

void Model::set_law(int cell, const std::string& law) {
  const tm_kernel& current = *kernels_[cell];
  if (law == current.law) return;
  const tm_kernel* next = law_kernel(cell, law);
  if (!next)
    throw std::invalid_argument("no kernel for law '" + law + "' on " + current.element + " that fits the cell's " +
                                "constants");
  ++law_revision_;
  if (next == initial_kernels_[cell]) {
    kernels_[cell] = next;
    return;
  }
  const bool same_layout = std::string(current.split) == "tensor" || std::string(current.split) == next->split;
  const bool same_prefix = same_layout && materials_[cell_material_[cell]].share_constants(current.law, next->law);
  kernels_[cell] = next;
  if (!same_prefix) {
    precompute(cell);
    ++consts_revision_;
  }
}

void Model::start_blend(int cell, const tm_kernel* from) {
  if (blend_from_.empty()) {
    blend_from_.assign(cell_count(), nullptr);
    blend_weight_.assign(cell_count(), 1.0);
  }
  blend_from_[cell] = from;
  blend_weight_[cell] = 0.0;
  ++law_revision_;
}

void Model::set_blend_weight(int cell, double weight) {
  if (blend_from_.empty()) return;
  if (weight >= 1.0) {
    if (blend_from_[cell]) ++law_revision_;
    blend_from_[cell] = nullptr;
    blend_weight_[cell] = 1.0;
  } else {
    blend_weight_[cell] = weight;
  }
}

void Model::gather(int cell, std::span<const double> u, double* local) const {
  const auto nodes = cell_nodes(cell);
  for (std::size_t j = 0; j < nodes.size(); ++j)
    for (int a = 0; a < dim_; ++a) local[j * dim_ + a] = u[static_cast<std::size_t>(nodes[j]) * dim_ + a];
}

double Model::strain_energy(std::span<const double> u) const {
  double total = 0.0;
  double local[kMaxCellDofs];
  for (int cell = 0; cell < cell_count(); ++cell) {
    gather(cell, u, local);
    total += kernels_[cell]->energy(local, consts(cell));
  }
  return total;
}

namespace {

/// Below this many cells in a block the check stays on one thread.
constexpr int kParallelInversionCells = 4096;

}  // namespace

int Model::first_inverted_cell(std::span<const double> u) const {
  int first = cell_count();  // the smallest inverted cell: the same answer on any thread count
  for (const ElementBlock& block : mesh_->blocks) {
    const InversionCheck check(*block.element);
    const int begin = block.first_cell, end = block.first_cell + block.count();
#pragma omp parallel for schedule(static) reduction(min : first) if (end - begin >= kParallelInversionCells)
    for (int cell = begin; cell < end; ++cell) {
      const tm_kernel& kernel = *kernels_[cell];
      if (kernel.invertible || cell >= first) continue;  // invertible: defined through inversion, not a failure
      double local[kMaxCellDofs];
      gather(cell, u, local);
      if (check.at_quadrature_points(local, consts(cell), kernel.derived_params, kernel.quadrature_points)) {
        first = cell;
      } else if (check.checks_corners()) {
        add_rest_positions(cell, local);
        if (check.first_flat_corner(local) >= 0) first = cell;
      }
    }
    if (first < cell_count()) return first;
  }
  return -1;
}

void Model::add_rest_positions(int cell, double* local) const {
  const auto nodes = cell_nodes(cell);
  for (std::size_t j = 0; j < nodes.size(); ++j)
    for (int a = 0; a < dim_; ++a) local[j * dim_ + a] += mesh_->rest_positions[3 * nodes[j] + a];
}

void Model::apply_constraints(double t, std::span<double> u, bool static_load_factor) const {
  for (const PrescribedDof& p : prescribed_) u[p.dof] = prescribed_value(p, t, static_load_factor);
}

double Model::prescribed_value(const PrescribedDof& p, double t, bool static_load_factor) const {
  if (p.held) return p.amplitude;
  // A static solve reaches the full value at the last load step whatever the
  // time profile: the load factor scales it linearly.
  const double factor = static_load_factor ? t : profiles_[p.profile].factor(t);
  double value = p.amplitude * factor;
  if (p.rotation >= 0) {
    const double* x = &mesh_->rest_positions[3 * static_cast<std::size_t>(p.dof / dim_)];
    value += rotations_[p.rotation].displacement(x, factor)[p.dof % dim_];
  }
  return value;
}

}  // namespace tensormass
