// Meshes and checks shared by the refinement tests: a mixed quad4/tri3
// beam, areas, conformity, 2:1 balance and bitwise mesh equality.
#ifndef TENSORMASS_TESTS_REFINEMENT_CHECKS_HPP
#define TENSORMASS_TESTS_REFINEMENT_CHECKS_HPP

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "tensormass/common/errors.hpp"
#include "tensormass/mesh/mesh.hpp"
#include "tensormass/mesh/mesh_conformity.hpp"
#include "tensormass/meshing/beam.hpp"
#include "tensormass/refinement/hierarchical_mesh.hpp"

namespace refinement_test {

using tensormass::Mesh;

/// A 6 x 3 beam of 6 x 3 squares: tri3 for x < 3 (two per square), quad4
/// beyond; groups clamp, tip, body, phase_tri3, phase_quad4, plus the node
/// group "bottom" (y = 0).
inline Mesh mixed_beam(int nx = 6, int ny = 3) {
  tensormass::BeamSpec spec;
  spec.cells = {nx, ny, 1};
  spec.size = {6.0, 3.0, 1.0};
  spec.phases = {{"tri3", 0.5}, {"quad4", 0.5}};
  Mesh mesh = tensormass::make_beam(spec);
  mesh.add_node_group("bottom", [](double, double y, double) { return y == 0.0; });
  return mesh;
}

inline const double* position(const Mesh& mesh, int node) { return &mesh.rest_positions[3 * node]; }

/// Signed area of a cell (shoelace over its corners).
inline double cell_area(const Mesh& mesh, int cell) {
  const auto [b, local] = mesh.locate(cell);
  const auto nodes = mesh.blocks[b].cell_nodes(local);
  double sum = 0;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const double* p = position(mesh, nodes[k]);
    const double* q = position(mesh, nodes[(k + 1) % nodes.size()]);
    sum += p[0] * q[1] - q[0] * p[1];
  }
  return sum / 2;
}

inline double total_area(const Mesh& mesh) {
  double area = 0;
  for (int cell = 0; cell < mesh.cell_count(); ++cell) area += cell_area(mesh, cell);
  return area;
}

inline double edge_length(const Mesh& mesh, int a, int b) {
  return std::hypot(position(mesh, a)[0] - position(mesh, b)[0], position(mesh, a)[1] - position(mesh, b)[1]);
}

/// Directed edges (from, to) of every cell, with the cell using each.
inline std::map<std::pair<int, int>, std::vector<int>> directed_edges(const Mesh& mesh) {
  std::map<std::pair<int, int>, std::vector<int>> edges;
  for (int cell = 0; cell < mesh.cell_count(); ++cell) {
    const auto [b, local] = mesh.locate(cell);
    const auto nodes = mesh.blocks[b].cell_nodes(local);
    for (std::size_t k = 0; k < nodes.size(); ++k) edges[{nodes[k], nodes[(k + 1) % nodes.size()]}].push_back(cell);
  }
  return edges;
}

/// The leaf mesh is conforming (every interior edge shared by two cells
/// running it in opposite directions, the boundary as long as the
/// original's), every cell counter-clockwise, the area the original's,
/// and leaves sharing an edge differ by at most one level.
inline void expect_valid_leaf_mesh(const tensormass::HierarchicalMesh& hierarchy, const char* where) {
  const Mesh& mesh = hierarchy.leaf_mesh();
  const Mesh& original = hierarchy.original_mesh();
  const tensormass::ConformityReport conformity = tensormass::check_conformity(mesh);
  EXPECT_EQ(conformity.overused_faces, 0) << where;
  const auto boundary_length = [](const Mesh& m, const tensormass::ConformityReport& report) {
    double length = 0;
    for (const std::vector<int>& edge : report.boundary_faces) length += edge_length(m, edge[0], edge[1]);
    return length;
  };
  EXPECT_NEAR(boundary_length(mesh, conformity), boundary_length(original, tensormass::check_conformity(original)),
              1e-12)
      << where << ": a hanging node shows up as boundary edges inside";
  for (int cell = 0; cell < mesh.cell_count(); ++cell)
    EXPECT_GT(cell_area(mesh, cell), 0.0) << where << " cell " << cell;
  EXPECT_NEAR(total_area(mesh), total_area(original), 1e-12 * total_area(original)) << where;
  const std::vector<int> levels(hierarchy.leaf_levels().begin(), hierarchy.leaf_levels().end());
  const auto edges = directed_edges(mesh);
  for (const auto& [edge, cells] : edges) {
    EXPECT_EQ(cells.size(), 1u) << where << ": edge " << edge.first << "-" << edge.second << " run twice one way";
    const auto back = edges.find({edge.second, edge.first});
    if (back == edges.end()) continue;
    EXPECT_LE(std::abs(levels[cells[0]] - levels[back->second[0]]), 1)
        << where << ": 2:1 balance broken across edge " << edge.first << "-" << edge.second;
  }
}

/// Bitwise equality of two doubles arrays (0.0 and -0.0 differ).
inline bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

/// Nodes (bitwise), source ids, blocks and groups equal.
inline void expect_same_mesh(const Mesh& actual, const Mesh& expected) {
  EXPECT_EQ(actual.dim, expected.dim);
  EXPECT_TRUE(same_bits(actual.rest_positions, expected.rest_positions)) << "rest positions";
  EXPECT_EQ(actual.node_source_ids, expected.node_source_ids);
  ASSERT_EQ(actual.blocks.size(), expected.blocks.size());
  for (std::size_t b = 0; b < expected.blocks.size(); ++b) {
    EXPECT_EQ(actual.blocks[b].element, expected.blocks[b].element) << "block " << b;
    EXPECT_EQ(actual.blocks[b].connectivity, expected.blocks[b].connectivity) << "block " << b;
    EXPECT_EQ(actual.blocks[b].source_ids, expected.blocks[b].source_ids) << "block " << b;
    EXPECT_EQ(actual.blocks[b].first_cell, expected.blocks[b].first_cell) << "block " << b;
  }
  ASSERT_EQ(actual.groups.size(), expected.groups.size());
  for (std::size_t g = 0; g < expected.groups.size(); ++g) {
    const tensormass::Group& a = actual.groups[g];
    const tensormass::Group& e = expected.groups[g];
    EXPECT_EQ(a.name, e.name);
    EXPECT_EQ(a.dim, e.dim) << e.name;
    EXPECT_EQ(a.nodes, e.nodes) << e.name;
    EXPECT_EQ(a.cells, e.cells) << e.name;
    EXPECT_EQ(a.facets.offsets, e.facets.offsets) << e.name;
    EXPECT_EQ(a.facets.nodes, e.facets.nodes) << e.name;
    EXPECT_EQ(a.facets.orders, e.facets.orders) << e.name;
  }
  EXPECT_EQ(actual.source, expected.source);
}

/// `action` throws an InputError whose message contains `words`.
template <typename Action>
void expect_input_error(Action action, const std::string& words) {
  try {
    action();
    ADD_FAILURE() << "no error, expected one mentioning '" << words << "'";
  } catch (const tensormass::InputError& error) {
    EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
  }
}

/// Every leaf-mesh cell, for marking all.
inline std::vector<int> all_cells(const Mesh& mesh) {
  std::vector<int> cells(static_cast<std::size_t>(mesh.cell_count()));
  for (int cell = 0; cell < mesh.cell_count(); ++cell) cells[static_cast<std::size_t>(cell)] = cell;
  return cells;
}

}  // namespace refinement_test

#endif
