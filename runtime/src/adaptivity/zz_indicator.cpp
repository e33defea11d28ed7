#include "tensormass/adaptivity/zz_indicator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass {
namespace {

// Bounds of the stack buffers of one cell; checked per cell against its kernel.
constexpr int kMaxNodes = kMaxCellNodes;
constexpr int kMaxPoints = 27;

/// Throws std::logic_error unless the cell's kernel fits its element and the buffers.
void check_kernel(const tm_kernel& kernel, const tm_element_info& element, const Mesh& mesh, int cell, int dim) {
  if (kernel.quadrature_points == element.quadrature_points && kernel.nodes == element.nodes && kernel.dim == dim &&
      kernel.nodes <= kMaxNodes && kernel.quadrature_points <= kMaxPoints)
    return;
  throw std::logic_error("R_ZZ: the kernel " + std::string(kernel.law) + "/" + kernel.element + "/" + kernel.split +
                         " of " + mesh.describe_cell(cell) + " does not fit element " + element.name +
                         " (quadrature points, nodes or dimension)");
}

/// The compact symmetric part of P (D by D, row-major): 2D xx, yy, xy; 3D xx, yy, zz, yz, xz, xy.
template <int D>
inline void symmetric_part(const double* P, double* s) {
  if constexpr (D == 2) {
    s[0] = P[0];
    s[1] = P[3];
    s[2] = 0.5 * (P[1] + P[2]);
  } else {
    s[0] = P[0];
    s[1] = P[4];
    s[2] = P[8];
    s[3] = 0.5 * (P[5] + P[7]);
    s[4] = 0.5 * (P[2] + P[6]);
    s[5] = 0.5 * (P[1] + P[3]);
  }
}

/// s : C^-1 : s for the isotropic compliance (see the header).
template <int D>
inline double compliance_energy(const double* s, double lam, double mu) {
  constexpr int C = zz_stress_components(D);
  double ss = 0, trace = 0;
  for (int c = 0; c < D; ++c) {
    ss += s[c] * s[c];
    trace += s[c];
  }
  for (int c = D; c < C; ++c) ss += 2 * s[c] * s[c];
  return (ss - lam / (D * lam + 2 * mu) * trace * trace) / (2 * mu);
}

/// The cell's stress P at every quadrature point (Q by D by D), blended
/// like its forces while it blends.
template <int D>
inline void cell_stress(const Model& model, int cell, std::span<const double> u, double* local, double* P,
                        double* P_old) {
  const tm_kernel& kernel = model.kernel(cell);
  const double* consts = model.consts(cell);
  model.gather(cell, u, local);
  kernel.stress(local, consts, P);
  if (const tm_kernel* before = model.blend_from(cell)) {
    const double w = model.blend_weight(cell);
    before->stress(local, consts, P_old);
    for (int k = 0; k < kernel.quadrature_points * D * D; ++k) P[k] = w * P[k] + (1 - w) * P_old[k];
  }
}

template <int D>
void compute_dim(const Model& model, std::span<const double> u, std::span<double> indicator,
                 std::vector<double>& nodal_stress, std::vector<double>& nodal_volume) {
  constexpr int C = zz_stress_components(D);
  const Mesh& mesh = model.mesh();
  nodal_stress.assign(static_cast<std::size_t>(mesh.node_count()) * C, 0.0);
  nodal_volume.assign(static_cast<std::size_t>(mesh.node_count()), 0.0);
  double local[kMaxNodes * D];
  double P[kMaxPoints * D * D], P_old[kMaxPoints * D * D];

  // Pass 1: sum over the cells around each node of V_e s_bar_e = integral of s_h, and of V_e.
  for (const ElementBlock& block : mesh.blocks) {
    for (int local_cell = 0; local_cell < block.count(); ++local_cell) {
      const int cell = block.first_cell + local_cell;
      const tm_kernel& kernel = model.kernel(cell);
      check_kernel(kernel, *block.element, mesh, cell, D);
      cell_stress<D>(model, cell, u, local, P, P_old);
      const double* consts = model.consts(cell);
      const int stride = 1 + D * kernel.nodes;
      double integral[C] = {};
      double volume = 0;
      for (int q = 0; q < kernel.quadrature_points; ++q) {
        const double w = consts[kernel.derived_params + q * stride];
        double s[C];
        symmetric_part<D>(P + q * D * D, s);
        for (int c = 0; c < C; ++c) integral[c] += w * s[c];
        volume += w;
      }
      for (int node : model.cell_nodes(cell)) {
        double* target = &nodal_stress[static_cast<std::size_t>(node) * C];
        for (int c = 0; c < C; ++c) target[c] += integral[c];
        nodal_volume[static_cast<std::size_t>(node)] += volume;
      }
    }
  }
  for (std::size_t node = 0; node < nodal_volume.size(); ++node) {
    if (nodal_volume[node] <= 0) continue;
    const double inverse = 1 / nodal_volume[node];
    for (int c = 0; c < C; ++c) nodal_stress[node * C + c] *= inverse;
  }

  // Pass 2: the energy norm of s* - s_h over each cell.
  for (const ElementBlock& block : mesh.blocks) {
    const tm_element_info& element = *block.element;
    for (int local_cell = 0; local_cell < block.count(); ++local_cell) {
      const int cell = block.first_cell + local_cell;
      const tm_kernel& kernel = model.kernel(cell);
      cell_stress<D>(model, cell, u, local, P, P_old);
      const double* consts = model.consts(cell);
      const auto [lam, mu] = model.material_laws(model.material(cell)).lame();
      const int stride = 1 + D * kernel.nodes;
      const auto nodes = model.cell_nodes(cell);
      double sum = 0;
      for (int q = 0; q < kernel.quadrature_points; ++q) {
        const double* N = element.shape_values + q * element.nodes;
        double e[C];
        symmetric_part<D>(P + q * D * D, e);
        for (int c = 0; c < C; ++c) e[c] = -e[c];
        for (std::size_t j = 0; j < nodes.size(); ++j) {
          const double* recovered = &nodal_stress[static_cast<std::size_t>(nodes[j]) * C];
          for (int c = 0; c < C; ++c) e[c] += N[j] * recovered[c];
        }
        sum += consts[kernel.derived_params + q * stride] * compliance_energy<D>(e, lam, mu);
      }
      // Round-off may make a zero sum slightly negative; a NaN stays NaN (max returns its first argument).
      indicator[static_cast<std::size_t>(cell)] = std::sqrt(std::max(sum, 0.0));
    }
  }
}

}  // namespace

void ZzIndicator::compute(const Model& model, std::span<const double> u, std::span<double> indicator) {
  if (u.size() != static_cast<std::size_t>(model.dof_count()))
    throw InputError("R_ZZ: the displacement has " + std::to_string(u.size()) + " values, the model " +
                     std::to_string(model.dof_count()) + " degrees of freedom");
  if (indicator.size() != static_cast<std::size_t>(model.cell_count()))
    throw InputError("R_ZZ: room for " + std::to_string(indicator.size()) + " indicators, the model has " +
                     std::to_string(model.cell_count()) + " cells");
  if (model.dim() == 2) compute_dim<2>(model, u, indicator, nodal_stress_, nodal_volume_);
  else compute_dim<3>(model, u, indicator, nodal_stress_, nodal_volume_);
}

std::vector<double> zz_indicator(const Model& model, std::span<const double> u) {
  std::vector<double> indicator(static_cast<std::size_t>(model.cell_count()));
  ZzIndicator().compute(model, u, indicator);
  return indicator;
}

std::vector<int> select_cells_at_threshold(std::span<const double> indicator, double threshold) {
  if (!(threshold >= 0 && threshold <= 1))
    throw InputError("R_ZZ threshold " + std::to_string(threshold) +
                     " is outside [0, 1] (cells at least threshold times the largest indicator are refined)");
  double largest = 0;
  for (std::size_t cell = 0; cell < indicator.size(); ++cell) {
    if (!std::isfinite(indicator[cell]) || indicator[cell] < 0)
      throw InputError("R_ZZ of cell " + std::to_string(cell) + " is " + std::to_string(indicator[cell]) +
                       ": an indicator must be finite and non-negative");
    largest = std::max(largest, indicator[cell]);
  }
  std::vector<int> cells;
  if (largest == 0) return cells;
  const double bound = threshold * largest;
  for (std::size_t cell = 0; cell < indicator.size(); ++cell)
    if (indicator[cell] >= bound) cells.push_back(static_cast<int>(cell));
  return cells;
}

}  // namespace tensormass
