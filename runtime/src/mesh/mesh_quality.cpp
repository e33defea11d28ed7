#include "tensormass/mesh/mesh_quality.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string_view>

#include "tensormass/kernels/law_parameters.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass {

namespace {

/// A corner and the `dim` neighbours whose edge vectors span its Jacobian.
struct Frame {
  int corner = 0;
  std::array<int, 3> neighbours{};
};

/// The corner frames of an element and the value a frame takes on the ideal shape.
struct CornerFrames {
  std::vector<Frame> frames;
  double scale = 1;  ///< 1 / (frame value of the ideal shape)
};

double ideal_scale(std::string_view name) {
  if (name.starts_with("tri") || name.starts_with("prism")) return 2 / std::sqrt(3.0);
  if (name.starts_with("tet") || name.starts_with("pyramid")) return std::sqrt(2.0);
  return 1;  // quadrangles and hexahedra: right angles
}

double det3(const double a[3], const double b[3], const double c[3]) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}

/// det of the frame's edge vectors in `coords` (`stride` values per node, first `dim` used).
double frame_det(const Frame& f, int dim, const double* coords, int stride) {
  double v[3][3] = {};
  for (int k = 0; k < dim; ++k)
    for (int c = 0; c < dim; ++c) v[k][c] = coords[f.neighbours[k] * stride + c] - coords[f.corner * stride + c];
  if (dim == 2) return v[0][0] * v[1][1] - v[0][1] * v[1][0];
  return det3(v[0], v[1], v[2]);
}

std::vector<std::vector<int>> corner_neighbours(const tm_element_info& element) {
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(element.nodes));
  for (int e = 0; e < element.edge_count; ++e) {
    const int a = element.edges[e * element.edge_size];
    const int b = element.edges[e * element.edge_size + 1];
    neighbours[static_cast<std::size_t>(a)].push_back(b);
    neighbours[static_cast<std::size_t>(b)].push_back(a);
  }
  return neighbours;
}

/// Frames oriented so that the reference element gives a positive determinant.
CornerFrames corner_frames(const tm_element_info& element) {
  CornerFrames result;
  result.scale = ideal_scale(element.name);
  const int dim = element.dim;
  const auto neighbours = corner_neighbours(element);
  for (int corner = 0; corner < element.nodes; ++corner) {
    const std::vector<int>& around = neighbours[static_cast<std::size_t>(corner)];
    const int n = static_cast<int>(around.size());
    if (n < dim) continue;
    // Every choice of `dim` neighbours when there are more (the pyramid apex), else the one.
    for (int skip = (n == dim ? -1 : 0); skip < (n == dim ? 0 : n); ++skip) {
      Frame frame;
      frame.corner = corner;
      int k = 0;
      for (int i = 0; i < n && k < dim; ++i)
        if (i != skip) frame.neighbours[static_cast<std::size_t>(k++)] = around[static_cast<std::size_t>(i)];
      if (n - (skip >= 0 ? 1 : 0) != dim) continue;
      if (frame_det(frame, dim, element.reference_nodes, dim) < 0) std::swap(frame.neighbours[0], frame.neighbours[1]);
      result.frames.push_back(frame);
    }
  }
  return result;
}

double distance(std::span<const double> xyz, int a, int b) {
  const double dx = xyz[3 * a] - xyz[3 * b];
  const double dy = xyz[3 * a + 1] - xyz[3 * b + 1];
  const double dz = xyz[3 * a + 2] - xyz[3 * b + 2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

double scaled_jacobian(const CornerFrames& frames, int dim, std::span<const double> xyz) {
  double worst = std::numeric_limits<double>::infinity();
  for (const Frame& f : frames.frames) {
    double lengths = 1;
    for (int k = 0; k < dim; ++k) lengths *= distance(xyz, f.corner, f.neighbours[static_cast<std::size_t>(k)]);
    const double value = lengths > 0 ? frame_det(f, dim, xyz.data(), 3) / lengths * frames.scale : 0.0;
    worst = std::min(worst, value);
  }
  return std::isfinite(worst) ? worst : 0.0;
}

/// A kernel able to precompute the rest Jacobians of `element` (any law, any split).
const tm_kernel* volume_kernel(const tm_element_info& element) {
  const tm_kernel* found = nullptr;
  for (const tm_kernel* kernel : Registry::instance().kernels())
    if (std::strcmp(kernel->element, element.name) == 0 && (!found || std::strcmp(kernel->split, "whole") == 0))
      found = kernel;
  return found;
}

double quadrature_volume(const tm_kernel* kernel, int dim, std::span<const double> xyz) {
  if (!kernel) return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> rest(static_cast<std::size_t>(kernel->nodes * kernel->dim));
  for (int n = 0; n < kernel->nodes; ++n)
    for (int c = 0; c < kernel->dim; ++c)
      rest[static_cast<std::size_t>(n * kernel->dim + c)] = xyz[static_cast<std::size_t>(3 * n + c)];
  const std::vector<double> params = admissible_parameters(*kernel);  // any: only the rest Jacobians are read
  std::vector<double> consts(static_cast<std::size_t>(kernel->consts));
  if (kernel->precompute(rest.data(), params.data(), kernel->params, consts.data()) != 0)
    return std::numeric_limits<double>::quiet_NaN();
  double volume = 0;
  const int stride = 1 + dim * kernel->nodes;
  for (int q = 0; q < kernel->quadrature_points; ++q)
    volume += consts[static_cast<std::size_t>(kernel->derived_params + q * stride)];
  return volume;
}

CellQuality quality(const tm_element_info& element, const CornerFrames& frames, const tm_kernel* kernel, int dim,
                    std::span<const double> xyz) {
  CellQuality result;
  result.scaled_jacobian = scaled_jacobian(frames, dim, xyz);
  result.edge_ratio = edge_ratio(element, xyz);
  result.volume = quadrature_volume(kernel, dim, xyz);
  result.inverted = !(result.scaled_jacobian > 0) || std::isnan(result.volume);
  return result;
}

}  // namespace

double scaled_jacobian(const tm_element_info& element, int dim, std::span<const double> xyz) {
  return scaled_jacobian(corner_frames(element), dim, xyz);
}

double edge_ratio(const tm_element_info& element, std::span<const double> xyz) {
  double shortest = std::numeric_limits<double>::infinity();
  double longest = 0;
  for (int e = 0; e < element.edge_count; ++e) {
    const double length = distance(xyz, element.edges[e * element.edge_size], element.edges[e * element.edge_size + 1]);
    shortest = std::min(shortest, length);
    longest = std::max(longest, length);
  }
  return shortest > 0 ? longest / shortest : std::numeric_limits<double>::infinity();
}

double cell_volume(const tm_element_info& element, int dim, std::span<const double> xyz) {
  return quadrature_volume(volume_kernel(element), dim, xyz);
}

CellQuality cell_quality(const tm_element_info& element, int dim, std::span<const double> xyz) {
  return quality(element, corner_frames(element), volume_kernel(element), dim, xyz);
}

std::vector<double> cell_coordinates(const Mesh& mesh, const ElementBlock& block, int local) {
  std::vector<double> xyz;
  xyz.reserve(3 * static_cast<std::size_t>(block.nodes_per_cell()));
  for (int node : block.cell_nodes(local))
    for (int c = 0; c < 3; ++c)
      xyz.push_back(mesh.rest_positions[3 * static_cast<std::size_t>(node) + static_cast<std::size_t>(c)]);
  return xyz;
}

MeshQuality mesh_quality(const Mesh& mesh) {
  MeshQuality result;
  result.cells.reserve(static_cast<std::size_t>(mesh.cell_count()));
  for (const ElementBlock& block : mesh.blocks) {
    const CornerFrames frames = corner_frames(*block.element);
    const tm_kernel* kernel = volume_kernel(*block.element);
    ElementTypeQuality summary;
    summary.element = block.element;
    summary.count = block.count();
    summary.min_scaled_jacobian = std::numeric_limits<double>::infinity();
    summary.max_scaled_jacobian = -std::numeric_limits<double>::infinity();
    for (int local = 0; local < block.count(); ++local) {
      const CellQuality cell = quality(*block.element, frames, kernel, mesh.dim, cell_coordinates(mesh, block, local));
      summary.min_scaled_jacobian = std::min(summary.min_scaled_jacobian, cell.scaled_jacobian);
      summary.max_scaled_jacobian = std::max(summary.max_scaled_jacobian, cell.scaled_jacobian);
      summary.max_edge_ratio = std::max(summary.max_edge_ratio, cell.edge_ratio);
      if (cell.inverted) {
        ++summary.inverted;
        result.inverted_cells.push_back(block.first_cell + local);
      } else {
        summary.volume += cell.volume;
      }
      result.cells.push_back(cell);
    }
    result.max_edge_ratio = std::max(result.max_edge_ratio, summary.max_edge_ratio);
    result.volume += summary.volume;
    result.types.push_back(summary);
  }
  return result;
}

}  // namespace tensormass
