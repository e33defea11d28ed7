/// \file beam_checks.hpp
/// Geometric checks of generated meshes: conformity (face matching), unique
/// nodes, shared mid-edge nodes, positive Jacobians and volumes (through the
/// registry's hooke kernels), boundary areas.
#ifndef TENSORMASS_TESTS_MESHING_BEAM_CHECKS_HPP
#define TENSORMASS_TESTS_MESHING_BEAM_CHECKS_HPP

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "support/test_meshes.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace tmtest {

using Point3 = std::array<double, 3>;

using meshtest::cells_per_type;

/// The boundary pieces of one cell: its faces (3D) or edges (2D), as node lists (corners first).
inline std::vector<std::vector<int>> cell_facets(const tensormass::Mesh& mesh, const tensormass::ElementBlock& block,
                                                 int local) {
  const tm_element_info& element = *block.element;
  const std::span<const int> nodes = block.cell_nodes(local);
  std::vector<std::vector<int>> facets;
  const bool edges = mesh.dim == 2;
  const int count = edges ? element.edge_count : element.face_count;
  for (int f = 0; f < count; ++f) {
    const int* first = edges ? element.edges + f * element.edge_size : element.faces + element.face_offsets[f];
    const int size = edges ? element.edge_size : element.face_sizes[f];
    std::vector<int> facet;
    for (int n = 0; n < size; ++n) facet.push_back(nodes[first[n]]);
    facets.push_back(facet);
  }
  return facets;
}

/// The corners of a facet of `order` (quadratic facets list corners, then as many mid-edge nodes).
inline std::vector<int> facet_corners(const std::vector<int>& facet, int order, int dim) {
  const std::size_t corners = dim == 2 ? 2 : (order == 2 ? facet.size() / 2 : facet.size());
  return {facet.begin(), facet.begin() + static_cast<std::ptrdiff_t>(corners)};
}

/// Area of a planar triangle or quadrilateral facet (3D) or length of an edge (2D).
inline double facet_measure(const tensormass::Mesh& mesh, const std::vector<int>& corners) {
  auto minus = [](Point3 a, Point3 b) { return Point3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
  auto cross_norm = [](Point3 a, Point3 b) {
    return std::hypot(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
  };
  std::vector<Point3> p;
  for (int node : corners) p.push_back(meshtest::position(mesh, node));
  if (p.size() == 2) return std::hypot(p[1][0] - p[0][0], p[1][1] - p[0][1]);
  if (p.size() == 3) return cross_norm(minus(p[1], p[0]), minus(p[2], p[0])) / 2;
  return cross_norm(minus(p[2], p[0]), minus(p[3], p[1])) / 2;
}

/// True when every corner lies on one face of the box [0, size].
inline bool on_box_boundary(const tensormass::Mesh& mesh, const std::vector<int>& corners,
                            const std::array<double, 3>& size) {
  for (int axis = 0; axis < mesh.dim; ++axis)
    for (double plane : {0.0, size[axis]}) {
      bool all = true;
      for (int node : corners) all = all && mesh.rest_positions[3 * node + axis] == plane;
      if (all) return true;
    }
  return false;
}

/// Every interior facet is shared by exactly two cells, every other one lies
/// on the box boundary, and the boundary facets cover the box's surface.
inline void expect_conforming(const tensormass::Mesh& mesh, const std::array<double, 3>& size) {
  std::map<std::vector<int>, std::pair<int, std::vector<int>>> seen;  // sorted corners -> count, corners
  for (const tensormass::ElementBlock& block : mesh.blocks)
    for (int local = 0; local < block.count(); ++local)
      for (const std::vector<int>& facet : cell_facets(mesh, block, local)) {
        const std::vector<int> corners = facet_corners(facet, block.element->order, mesh.dim);
        std::vector<int> key = corners;
        std::sort(key.begin(), key.end());
        auto& [n, cycle] = seen[key];
        ++n;
        cycle = corners;
      }
  double boundary = 0;
  int bad = 0;
  for (const auto& [key, entry] : seen) {
    const auto& [n, corners] = entry;
    if (n > 2 || (n == 1 && !on_box_boundary(mesh, corners, size))) ++bad;
    if (n == 1) boundary += facet_measure(mesh, corners);
  }
  EXPECT_EQ(bad, 0) << "facets that are neither shared by two cells nor on the box boundary";
  const double expected =
      mesh.dim == 2 ? 2 * (size[0] + size[1]) : 2 * (size[0] * size[1] + size[0] * size[2] + size[1] * size[2]);
  EXPECT_NEAR(boundary, expected, 1e-12 * expected);
}

/// No two nodes at the same position, and every node used by a cell.
inline void expect_nodes_unique_and_used(const tensormass::Mesh& mesh) {
  std::set<Point3> positions;
  for (int node = 0; node < mesh.node_count(); ++node) positions.insert(meshtest::position(mesh, node));
  EXPECT_EQ(static_cast<int>(positions.size()), mesh.node_count()) << "duplicate node positions";
  std::vector<char> used(mesh.node_count(), 0);
  for (const tensormass::ElementBlock& block : mesh.blocks)
    for (int node : block.connectivity) used[node] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << "nodes no cell uses";
}

/// Quadratic cells: each edge's mid node is shared and lies at the edge's midpoint.
inline void expect_mid_edge_nodes(const tensormass::Mesh& mesh) {
  std::map<std::pair<int, int>, int> mid_of_edge;
  int bad = 0;
  for (const tensormass::ElementBlock& block : mesh.blocks) {
    const tm_element_info& element = *block.element;
    if (element.edge_size != 3) continue;
    for (int local = 0; local < block.count(); ++local) {
      const std::span<const int> nodes = block.cell_nodes(local);
      for (int e = 0; e < element.edge_count; ++e) {
        const int a = nodes[element.edges[3 * e]], b = nodes[element.edges[3 * e + 1]];
        const int m = nodes[element.edges[3 * e + 2]];
        const auto [where, inserted] = mid_of_edge.emplace(std::minmax(a, b), m);
        if (!inserted && where->second != m) ++bad;
        for (int c = 0; c < 3; ++c)
          if (mesh.rest_positions[3 * m + c] != (mesh.rest_positions[3 * a + c] + mesh.rest_positions[3 * b + c]) / 2)
            ++bad;
      }
    }
  }
  EXPECT_EQ(bad, 0) << "mid-edge nodes not shared or not at the midpoint";
}

/// Volume (area in 2D) of each cell from the hooke kernel's precompute
/// (sum of w_q det J_q); fails the test on a non-positive Jacobian.
inline std::vector<double> cell_volumes(const tensormass::Mesh& mesh) {
  const double params[] = {1000.0, 0.3};
  std::vector<double> volumes;
  for (const tensormass::ElementBlock& block : mesh.blocks) {
    const tm_kernel& kernel = tensormass::Registry::instance().get("hooke", block.element->name, "whole");
    std::vector<double> rest(kernel.nodes * kernel.dim), consts(kernel.consts);
    for (int local = 0; local < block.count(); ++local) {
      const std::span<const int> nodes = block.cell_nodes(local);
      for (int n = 0; n < kernel.nodes; ++n)
        for (int c = 0; c < kernel.dim; ++c) rest[n * kernel.dim + c] = mesh.rest_positions[3 * nodes[n] + c];
      EXPECT_EQ(kernel.precompute(rest.data(), params, 2, consts.data()), 0)
          << mesh.describe_cell(block.first_cell + local) << " has a non-positive Jacobian";
      double volume = 0;
      for (int q = 0; q < kernel.quadrature_points; ++q)
        volume += consts[kernel.derived_params + q * (1 + kernel.dim * kernel.nodes)];
      volumes.push_back(volume);
    }
  }
  return volumes;
}

}  // namespace tmtest

#endif
