// MeshBuilder (mesh_builder.cpp) on raw nodes and elements given by hand:
// cells of the highest dimension sorted into blocks in registry order, the
// used nodes renumbered in file order with their file ids kept, facets and
// nodes of groups, repeated elements and groups of one name merged, and the
// InputErrors (non-finite coordinate, unknown node, duplicate node id, no
// cells, a 2D mesh off the plane z = 0) naming the file and line.
#include <gtest/gtest.h>

#include <array>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh/mesh_builder.hpp"
#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass::detail {
namespace {

using test_support::expect_contains;

const Shape& shape(const char* name) {
  const Shape* found = find_shape(name);
  if (!found) throw std::logic_error(std::string("no shape ") + name);
  return *found;
}

void add_node(MeshBuilder& builder, long id, std::array<double, 3> xyz, long line) {
  builder.add_node(id, xyz.data(), Location{line, false});
}

void add_element(MeshBuilder& builder, const char* name, long id, std::vector<long> nodes, std::vector<long> groups,
                 long line) {
  builder.add_element(shape(name), id, nodes, groups, Location{line, false});
}

GroupInfo named(long key) {
  static const std::map<long, GroupInfo> names{
      {1, {"body", -1}}, {2, {"body", -1}}, {3, {"right", -1}}, {4, {"corner", -1}}, {5, {"copy", -1}}};
  return names.at(key);
}

/// A square of one quad4 with two tri3 beside it, a facet group on the right
/// edge, a point group, an unused node and the quad written twice.
MeshBuilder square_and_triangles() {
  MeshBuilder builder("plate.msh", "element");
  // File order differs from id order: nodes are numbered in file order.
  add_node(builder, 12, {1, 1, 0}, 3);
  add_node(builder, 10, {0, 0, 0}, 4);
  add_node(builder, 11, {1, 0, 0}, 5);
  add_node(builder, 13, {0, 1, 0}, 6);
  add_node(builder, 99, {5, 5, 0}, 7);  // in no element
  add_node(builder, 14, {2, 0, 0}, 8);
  add_node(builder, 15, {2, 1, 0}, 9);
  add_element(builder, "quad4", 1, {10, 11, 12, 13}, {1}, 20);
  add_element(builder, "tri3", 2, {11, 14, 15}, {1}, 21);
  add_element(builder, "tri3", 3, {11, 15, 12}, {2}, 22);
  add_element(builder, "line2", 4, {14, 15}, {3}, 23);
  add_element(builder, "point", 5, {10}, {4}, 24);
  add_element(builder, "quad4", 1, {10, 11, 12, 13}, {5}, 25);  // again, for another group
  return builder;
}

/// The file ids of a list of mesh nodes.
std::vector<long> ids(const Mesh& mesh, const std::vector<int>& nodes) {
  std::vector<long> result;
  for (int node : nodes) result.push_back(mesh.node_source_ids[static_cast<std::size_t>(node)]);
  return result;
}

std::string build_error(MeshBuilder builder) {
  try {
    builder.build(named);
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(MeshBuilder, FindsShapesByName) {
  EXPECT_EQ(find_shape("tri3")->nodes, 3);
  EXPECT_EQ(find_shape("tri3")->dim, 2);
  EXPECT_EQ(find_shape("line3")->nodes, 3);
  EXPECT_EQ(find_shape("line3")->order, 2);
  EXPECT_EQ(find_shape("point")->dim, 0);
  EXPECT_EQ(find_shape("point")->element, nullptr);
  EXPECT_EQ(find_shape("tet4")->element, Registry::instance().element("tet4"));
  EXPECT_EQ(shape_of(Registry::instance().element("hex8")), find_shape("hex8"));
  EXPECT_EQ(find_shape("no_such_shape"), nullptr);
}

TEST(MeshBuilder, UsedNodesAreRenumberedInFileOrderKeepingTheirIds) {
  const Mesh mesh = square_and_triangles().build(named);
  EXPECT_EQ(mesh.dim, 2);
  EXPECT_EQ(mesh.source, "plate.msh");
  EXPECT_EQ(mesh.node_source_ids, (std::vector<long>{12, 10, 11, 13, 14, 15}));
  ASSERT_EQ(mesh.node_count(), 6);
  EXPECT_EQ(mesh.rest_positions[0], 1.0);  // node 12 at (1, 1)
  EXPECT_EQ(mesh.rest_positions[1], 1.0);
  EXPECT_EQ(mesh.rest_positions[3 * 4], 2.0);  // node 14 at (2, 0)
  EXPECT_EQ(mesh.rest_positions[3 * 4 + 1], 0.0);
}

TEST(MeshBuilder, CellsAreSortedIntoBlocksInRegistryOrderAndRepeatsMerged) {
  const Mesh mesh = square_and_triangles().build(named);
  EXPECT_EQ(mesh.cell_count(), 3);
  std::vector<std::string> expected;
  for (const tm_element_info* element : Registry::instance().elements())
    if (std::string(element->name) == "tri3" || std::string(element->name) == "quad4")
      expected.push_back(element->name);
  std::vector<std::string> names;
  for (const ElementBlock& block : mesh.blocks) names.push_back(block.element->name);
  EXPECT_EQ(names, expected);
  int first = 0;
  for (const ElementBlock& block : mesh.blocks) {
    SCOPED_TRACE(block.element->name);
    EXPECT_EQ(block.first_cell, first);
    first += block.count();
    if (std::string(block.element->name) == "tri3") {
      EXPECT_EQ(block.source_ids, (std::vector<long>{2, 3}));
      EXPECT_EQ(ids(mesh, block.connectivity), (std::vector<long>{11, 14, 15, 11, 15, 12}));
    } else {
      EXPECT_EQ(block.source_ids, (std::vector<long>{1}));
      EXPECT_EQ(ids(mesh, block.connectivity), (std::vector<long>{10, 11, 12, 13}));
    }
  }
}

TEST(MeshBuilder, GroupsOfOneNameAreMergedWithTheirCellsAndNodes) {
  const Mesh mesh = square_and_triangles().build(named);
  const Group* body = mesh.group("body");
  ASSERT_NE(body, nullptr);
  EXPECT_EQ(body->dim, 2);
  EXPECT_EQ(body->cells, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(body->nodes, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(body->facets.count(), 0);
  int named_body = 0;
  for (const Group& group : mesh.groups) named_body += group.name == "body";
  EXPECT_EQ(named_body, 1);
}

TEST(MeshBuilder, EdgesAreTheFacetsOfTheirGroup) {
  const Mesh mesh = square_and_triangles().build(named);
  const Group* right = mesh.group("right");
  ASSERT_NE(right, nullptr);
  EXPECT_EQ(right->dim, 1);
  EXPECT_TRUE(right->cells.empty());
  EXPECT_EQ(ids(mesh, right->nodes), (std::vector<long>{14, 15}));
  ASSERT_EQ(right->facets.count(), 1);
  EXPECT_EQ(ids(mesh, right->facets.nodes), (std::vector<long>{14, 15}));
  EXPECT_EQ(right->facets.orders, (std::vector<int>{1}));
}

TEST(MeshBuilder, APointGroupHoldsItsNode) {
  const Mesh mesh = square_and_triangles().build(named);
  const Group* corner = mesh.group("corner");
  ASSERT_NE(corner, nullptr);
  EXPECT_EQ(corner->dim, 0);
  EXPECT_EQ(ids(mesh, corner->nodes), (std::vector<long>{10}));
  EXPECT_TRUE(corner->cells.empty());
}

TEST(MeshBuilder, ARepeatedElementBelongsToTheGroupsOfEachCopy) {
  const Mesh mesh = square_and_triangles().build(named);
  const Group* copy = mesh.group("copy");
  ASSERT_NE(copy, nullptr);
  ASSERT_EQ(copy->cells.size(), 1u);
  const auto [block, local] = mesh.locate(copy->cells[0]);
  EXPECT_STREQ(mesh.blocks[static_cast<std::size_t>(block)].element->name, "quad4");
  EXPECT_EQ(mesh.blocks[static_cast<std::size_t>(block)].source_ids[static_cast<std::size_t>(local)], 1);
  EXPECT_EQ(ids(mesh, copy->nodes), (std::vector<long>{12, 10, 11, 13}));
}

TEST(MeshBuilder, ANonFiniteCoordinateIsAnErrorAtItsLine) {
  MeshBuilder builder("plate.msh", "element");
  const double xyz[3] = {0.0, std::numeric_limits<double>::quiet_NaN(), 0.0};
  try {
    builder.add_node(7, xyz, Location{42, false});
    FAIL() << "no error";
  } catch (const InputError& error) {
    expect_contains(error.what(), {"plate.msh:42: node 7 has a non-finite coordinate (y = "});
  }
}

TEST(MeshBuilder, AnUndefinedNodeIsAnErrorNamingTheElement) {
  MeshBuilder builder = square_and_triangles();
  add_element(builder, "tri3", 8, {11, 14, 77}, {1}, 30);
  EXPECT_EQ(build_error(std::move(builder)),
            "plate.msh:30: element 8 (tri3) refers to node 77, which the file does not define");
}

TEST(MeshBuilder, ADuplicateNodeIdIsAnErrorAtItsSecondLine) {
  MeshBuilder builder = square_and_triangles();
  add_node(builder, 13, {3, 3, 0}, 10);
  const std::string message = build_error(std::move(builder));
  expect_contains(message, {"plate.msh:10: duplicate node id 13"});
}

TEST(MeshBuilder, NoCellsAreErrors) {
  EXPECT_EQ(build_error(MeshBuilder("empty.msh", "element")), "empty.msh: the file has no elements");
  MeshBuilder lines("lines.msh", "element");
  add_node(lines, 1, {0, 0, 0}, 2);
  add_node(lines, 2, {1, 0, 0}, 3);
  add_element(lines, "line2", 1, {1, 2}, {3}, 4);
  EXPECT_EQ(build_error(std::move(lines)), "lines.msh: no 2D or 3D elements (the highest element dimension is 1)");
}

TEST(MeshBuilder, A2dMeshOffThePlaneZ0IsAnErrorNamingTheNode) {
  MeshBuilder builder("tilted.msh", "cell");
  add_node(builder, 1, {0, 0, 0}, 2);
  add_node(builder, 2, {1, 0, 0}, 3);
  add_node(builder, 3, {0, 1, 0.5}, 4);
  add_element(builder, "tri3", 1, {1, 2, 3}, {1}, 5);
  expect_contains(build_error(std::move(builder)),
                  {"tilted.msh: the highest elements are 2D, but node 3 has z = 0.5", "plane z = 0"});
}

}  // namespace
}  // namespace tensormass::detail
