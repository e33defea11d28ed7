// Meshes from arrays (mesh_arrays.cpp): a mesh taken apart into arrays and
// rebuilt is the same mesh, meshio's element names are accepted, groups of
// points and cells (facets too) are built, and every bad array is an
// InputError naming the array and index.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "support/cantilever.hpp"
#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/mesh/mesh_arrays.hpp"

namespace tensormass {
namespace {

using test_support::expect_contains;

/// The mesh's points, cells (by block) and node groups as arrays.
MeshArrays arrays_of(const Mesh& mesh) {
  MeshArrays arrays;
  arrays.points = mesh.rest_positions;
  for (const ElementBlock& block : mesh.blocks)
    arrays.cells.push_back({block.element->name, {block.connectivity.begin(), block.connectivity.end()}});
  for (const Group& group : mesh.groups)
    arrays.point_groups.push_back({group.name, {group.nodes.begin(), group.nodes.end()}});
  return arrays;
}

/// One unit tet with an extra triangle on its base face.
MeshArrays one_tet() {
  MeshArrays arrays;
  arrays.points = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  arrays.cells = {{"tetra", {0, 1, 2, 3}}, {"triangle", {0, 2, 1}}};
  return arrays;
}

void expect_input_error(const MeshArrays& arrays, const std::vector<std::string>& parts) {
  try {
    mesh_from_arrays(arrays, "arrays");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    expect_contains(e.what(), parts);
  }
}

TEST(MeshArrays, RebuildsTheSameMesh) {
  for (const auto& [dim, cut] : {std::pair{3, std::string("hex8")}, {3, "tet6"}, {2, "tri3"}, {3, "prism6"}}) {
    SCOPED_TRACE(cut);
    const Mesh original = test::beam(dim, cut, {4, 2, 2});
    const Mesh rebuilt = mesh_from_arrays(arrays_of(original), "arrays");
    EXPECT_EQ(rebuilt.dim, original.dim);
    EXPECT_EQ(rebuilt.rest_positions, original.rest_positions);
    ASSERT_EQ(rebuilt.blocks.size(), original.blocks.size());
    for (std::size_t b = 0; b < rebuilt.blocks.size(); ++b) {
      EXPECT_EQ(rebuilt.blocks[b].element, original.blocks[b].element);
      EXPECT_EQ(rebuilt.blocks[b].connectivity, original.blocks[b].connectivity);
    }
    for (const Group& group : original.groups) {
      ASSERT_NE(rebuilt.group(group.name), nullptr) << group.name;
      EXPECT_EQ(rebuilt.group(group.name)->nodes, group.nodes) << group.name;
    }
  }
}

TEST(MeshArrays, MeshioNamesCellGroupsAndFacets) {
  MeshArrays arrays = one_tet();
  arrays.point_groups = {{"apex", {3}}};
  arrays.cell_groups = {{"body", {0}}, {"base", {1}}};
  const Mesh mesh = mesh_from_arrays(arrays, "arrays");
  ASSERT_EQ(mesh.blocks.size(), 1u);
  EXPECT_EQ(std::string(mesh.blocks[0].element->name), "tet4");
  EXPECT_EQ(mesh.group("apex")->nodes, std::vector<int>({3}));
  EXPECT_EQ(mesh.group("body")->cells, std::vector<int>({0}));
  EXPECT_EQ(mesh.group("base")->facets.count(), 1);
  EXPECT_EQ(mesh.group("base")->nodes, std::vector<int>({0, 1, 2}));
}

TEST(MeshArrays, BadArraysAreInputErrors) {
  MeshArrays unknown = one_tet();
  unknown.cells[0].element = "tetrahedron";
  expect_input_error(unknown, {"arrays", "unknown element 'tetrahedron'", "tet4 (tetra)"});
  MeshArrays short_row = one_tet();
  short_row.cells[0].nodes.pop_back();
  expect_input_error(short_row, {"tetra", "4 points each", "3 indices"});
  MeshArrays out_of_range = one_tet();
  out_of_range.cells[0].nodes[2] = 7;
  expect_input_error(out_of_range, {"tetra cell 0", "point 7", "0..3"});
  MeshArrays negative = one_tet();
  negative.point_groups = {{"apex", {-1}}};
  expect_input_error(negative, {"point group 'apex'", "point -1"});
  MeshArrays bad_cell_group = one_tet();
  bad_cell_group.cell_groups = {{"body", {2}}};
  expect_input_error(bad_cell_group, {"cell group 'body'", "cell 2", "0..1"});
  MeshArrays unused = one_tet();
  unused.points.insert(unused.points.end(), {5, 5, 5});
  expect_input_error(unused, {"1 of the 5 points belong to no cell"});
  MeshArrays not_finite = one_tet();
  not_finite.points[4] = std::nan("");
  expect_input_error(not_finite, {"arrays"});
}

}  // namespace
}  // namespace tensormass
