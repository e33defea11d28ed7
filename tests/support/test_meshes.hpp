/// \file test_meshes.hpp
/// Helpers of the tests that read and check meshes (io readers, mesh
/// quality, mesh-info): paths of the committed test meshes
/// (tests/data/meshes), their expected.json (read with nlohmann-json), node
/// positions, cells per type, mesh comparison and a read_mesh InputError
/// matcher.
#ifndef TENSORMASS_TESTS_SUPPORT_TEST_MESHES_HPP
#define TENSORMASS_TESTS_SUPPORT_TEST_MESHES_HPP

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace meshtest {

inline std::string data_dir() { return std::string(TENSORMASS_SOURCE_DIR) + "/tests/data/meshes/"; }
inline std::string data_file(const std::string& name) { return data_dir() + name; }

/// The four Gmsh encodings written by make_meshes.py.
inline const std::vector<std::string>& encodings() {
  static const std::vector<std::string> list{"msh22", "msh22b", "msh41", "msh41b"};
  return list;
}

/// Runs read_mesh(path); expects an InputError whose message contains every piece.
inline void expect_input_error(const std::string& path, const std::vector<std::string>& pieces) {
  try {
    tensormass::read_mesh(path);
    ADD_FAILURE() << path << ": read without error";
  } catch (const tensormass::InputError& error) {
    test_support::expect_contains(error.what(), pieces);
  } catch (const std::exception& error) {
    ADD_FAILURE() << path << ": not an InputError: " << error.what();
  }
}

/// tests/data/meshes/expected.json: what Gmsh reports of each test mesh.
inline const nlohmann::json& expected_meshes() {
  static const nlohmann::json json = nlohmann::json::parse(test_support::read_file(data_file("expected.json")));
  return json;
}

// --- Mesh comparison ----------------------------------------------------------

inline std::array<double, 3> position(const tensormass::Mesh& mesh, int node) {
  const auto n = static_cast<std::size_t>(node);
  return {mesh.rest_positions[3 * n], mesh.rest_positions[3 * n + 1], mesh.rest_positions[3 * n + 2]};
}

/// Cells per reference element name.
inline std::map<std::string, int> cells_per_type(const tensormass::Mesh& mesh) {
  std::map<std::string, int> counts;
  for (const tensormass::ElementBlock& block : mesh.blocks) counts[block.element->name] += block.count();
  return counts;
}

/// Sorted coordinates of `nodes`.
inline std::vector<std::array<double, 3>> positions(const tensormass::Mesh& mesh, const std::vector<int>& nodes) {
  std::vector<std::array<double, 3>> result;
  for (int node : nodes) result.push_back(position(mesh, node));
  std::sort(result.begin(), result.end());
  return result;
}

/// Same cells (type, order, node coordinates in order), compared by position so
/// that node numbering may differ.
inline void expect_same_cells(const tensormass::Mesh& a, const tensormass::Mesh& b) {
  ASSERT_EQ(a.dim, b.dim);
  ASSERT_EQ(a.node_count(), b.node_count());
  ASSERT_EQ(a.blocks.size(), b.blocks.size());
  for (std::size_t k = 0; k < a.blocks.size(); ++k) {
    const tensormass::ElementBlock& x = a.blocks[k];
    const tensormass::ElementBlock& y = b.blocks[k];
    ASSERT_EQ(x.element, y.element);
    ASSERT_EQ(x.count(), y.count()) << x.element->name;
    EXPECT_EQ(x.first_cell, y.first_cell);
    for (int c = 0; c < x.count(); ++c)
      for (int j = 0; j < x.nodes_per_cell(); ++j)
        ASSERT_EQ(position(a, x.cell_nodes(c)[static_cast<std::size_t>(j)]),
                  position(b, y.cell_nodes(c)[static_cast<std::size_t>(j)]))
            << x.element->name << " cell " << c << " node " << j;
  }
}

/// Identical meshes (same numbering), groups included; source ids optional.
/// Coordinates may differ in the last digit (Gmsh writes ASCII with 16 digits).
inline void expect_identical(const tensormass::Mesh& a, const tensormass::Mesh& b, bool compare_element_ids) {
  EXPECT_EQ(a.dim, b.dim);
  ASSERT_EQ(a.rest_positions.size(), b.rest_positions.size());
  for (std::size_t i = 0; i < a.rest_positions.size(); ++i)
    ASSERT_NEAR(a.rest_positions[i], b.rest_positions[i], 1e-15 * std::max(1.0, std::abs(a.rest_positions[i])))
        << "coordinate " << i;
  EXPECT_EQ(a.node_source_ids, b.node_source_ids);
  EXPECT_EQ(a.cell_numbers, b.cell_numbers);
  ASSERT_EQ(a.blocks.size(), b.blocks.size());
  for (std::size_t k = 0; k < a.blocks.size(); ++k) {
    EXPECT_EQ(a.blocks[k].element, b.blocks[k].element);
    EXPECT_EQ(a.blocks[k].connectivity, b.blocks[k].connectivity);
    EXPECT_EQ(a.blocks[k].first_cell, b.blocks[k].first_cell);
    if (compare_element_ids) {
      EXPECT_EQ(a.blocks[k].source_ids, b.blocks[k].source_ids);
    }
  }
  ASSERT_EQ(a.groups.size(), b.groups.size());
  for (std::size_t g = 0; g < a.groups.size(); ++g) {
    EXPECT_EQ(a.groups[g].name, b.groups[g].name);
    EXPECT_EQ(a.groups[g].dim, b.groups[g].dim);
    EXPECT_EQ(a.groups[g].nodes, b.groups[g].nodes);
    EXPECT_EQ(a.groups[g].cells, b.groups[g].cells);
    EXPECT_EQ(a.groups[g].facets.offsets, b.groups[g].facets.offsets);
    EXPECT_EQ(a.groups[g].facets.nodes, b.groups[g].facets.nodes);
    EXPECT_EQ(a.groups[g].facets.orders, b.groups[g].facets.orders);
  }
}

/// Reads the meshio conversion `vtk_file` (.vtu or .vtk) of the test mesh
/// `stem` and expects the cells of its Gmsh 4.1 file and one group
/// "region_TAG" per physical group of expected.json, with the same cells,
/// facets and node positions as the Gmsh group.
inline void expect_same_mesh_as_gmsh(const std::string& vtk_file, const std::string& stem) {
  const tensormass::Mesh gmsh = tensormass::read_mesh(data_file(stem + ".msh41.msh"));
  const tensormass::Mesh vtk = tensormass::read_mesh(data_file(vtk_file));
  expect_same_cells(gmsh, vtk);
  const nlohmann::json& groups = expected_meshes()[stem]["groups"];
  ASSERT_EQ(vtk.groups.size(), groups.size());
  for (const auto& [name, expected] : groups.items()) {
    const tensormass::Group* from_gmsh = gmsh.group(name);
    const tensormass::Group* from_vtk = vtk.group("region_" + std::to_string(expected["tag"].get<int>()));
    ASSERT_NE(from_gmsh, nullptr);
    ASSERT_NE(from_vtk, nullptr) << name;
    EXPECT_EQ(from_vtk->dim, from_gmsh->dim) << name;
    EXPECT_EQ(from_vtk->cells, from_gmsh->cells) << name;
    EXPECT_EQ(from_vtk->facets.count(), from_gmsh->facets.count()) << name;
    EXPECT_EQ(positions(vtk, from_vtk->nodes), positions(gmsh, from_gmsh->nodes)) << name;
  }
}

/// A gtest parameter name made of `file`: every character that is not a letter or digit as '_'.
inline std::string test_name_of(std::string file) {
  for (char& c : file)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return file;
}

}  // namespace meshtest

#endif
