// Gmsh reader on meshes written by Gmsh itself (tests/data/meshes, made by
// make_meshes.sh): counts equal to what Gmsh reports (expected.json), the
// four encodings give identical meshes, node reordering gives positive
// volumes summing to the geometry's and mid-edge nodes at edge midpoints.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "support/test_meshes.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/mesh/mesh.hpp"
#include "tensormass/mesh/mesh_quality.hpp"

namespace {

using meshtest::expected_meshes;
using Json = nlohmann::json;
using tensormass::Mesh;

std::vector<std::string> stems() {
  std::vector<std::string> result;
  for (const auto& [stem, value] : expected_meshes().items()) result.push_back(stem);
  return result;
}

std::string file_of(const std::string& stem, const std::string& encoding) {
  return meshtest::data_file(stem + "." + encoding + ".msh");
}

struct Case {
  std::string stem;
  std::string encoding;
};

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  for (const std::string& stem : stems())
    for (const std::string& encoding : meshtest::encodings()) cases.push_back({stem, encoding});
  return cases;
}

class GmshFile : public testing::TestWithParam<Case> {
 protected:
  void SetUp() override { mesh_ = tensormass::read_mesh(file_of(GetParam().stem, GetParam().encoding)); }
  const Json& expected() const { return expected_meshes()[GetParam().stem]; }
  Mesh mesh_;
};

TEST_P(GmshFile, CountsMatchGmsh) {
  EXPECT_EQ(mesh_.dim, expected()["dim"].get<int>());
  EXPECT_EQ(mesh_.node_count(), expected()["nodes"].get<int>());
  std::map<std::string, int> counts;
  for (const tensormass::ElementBlock& block : mesh_.blocks) counts[block.element->name] = block.count();
  std::map<std::string, int> wanted;
  for (const auto& [name, count] : expected()["cells"].items()) wanted[name] = count.get<int>();
  EXPECT_EQ(counts, wanted);
}

TEST_P(GmshFile, GroupsMatchGmsh) {
  const Json& groups = expected()["groups"];
  ASSERT_EQ(mesh_.groups.size(), groups.size());
  for (const auto& [name, want] : groups.items()) {
    const tensormass::Group* group = mesh_.group(name);
    ASSERT_NE(group, nullptr) << name;
    EXPECT_EQ(group->dim, want["dim"].get<int>()) << name;
    EXPECT_EQ(static_cast<int>(group->nodes.size()), want["nodes"].get<int>()) << name;
    EXPECT_EQ(static_cast<int>(group->cells.size()), want["cells"].get<int>()) << name;
    EXPECT_EQ(group->facets.count(), want["facets"].get<int>()) << name;
    EXPECT_TRUE(std::is_sorted(group->nodes.begin(), group->nodes.end()));
  }
}

TEST_P(GmshFile, CellVolumesArePositiveAndSumToTheGeometry) {
  double total = 0;
  for (const tensormass::ElementBlock& block : mesh_.blocks)
    for (int c = 0; c < block.count(); ++c) {
      const std::vector<double> xyz = tensormass::cell_coordinates(mesh_, block, c);
      const double volume = tensormass::cell_volume(*block.element, mesh_.dim, xyz);
      ASSERT_GT(volume, 0) << mesh_.describe_cell(block.first_cell + c);
      EXPECT_GT(tensormass::scaled_jacobian(*block.element, mesh_.dim, xyz), 0)
          << mesh_.describe_cell(block.first_cell + c);
      total += volume;
    }
  EXPECT_NEAR(total, expected()["volume"].get<double>(), 1e-12 * expected()["volume"].get<double>());
}

TEST_P(GmshFile, MidEdgeNodesAreEdgeMidpoints) {
  for (const tensormass::ElementBlock& block : mesh_.blocks) {
    const tm_element_info& e = *block.element;
    if (e.edge_size != 3) continue;
    for (int c = 0; c < block.count(); ++c)
      for (int k = 0; k < e.edge_count; ++k) {
        const auto nodes = block.cell_nodes(c);
        const auto a = meshtest::position(mesh_, nodes[static_cast<std::size_t>(e.edges[3 * k])]);
        const auto b = meshtest::position(mesh_, nodes[static_cast<std::size_t>(e.edges[3 * k + 1])]);
        const auto m = meshtest::position(mesh_, nodes[static_cast<std::size_t>(e.edges[3 * k + 2])]);
        for (int x = 0; x < 3; ++x)
          ASSERT_NEAR(m[x], 0.5 * (a[x] + b[x]), 1e-9) << e.name << " cell " << c << " edge " << k;
      }
  }
}

TEST_P(GmshFile, FacetsHaveCornersFirstThenMidNodes) {
  for (const tensormass::Group& group : mesh_.groups)
    for (int f = 0; f < group.facets.count(); ++f) {
      const int first = group.facets.offsets[static_cast<std::size_t>(f)];
      const int size = group.facets.offsets[static_cast<std::size_t>(f) + 1] - first;
      const int order = group.facets.orders[static_cast<std::size_t>(f)];
      ASSERT_TRUE(order == 1 || order == 2);
      if (order == 1) continue;
      const int corners = size == 3 ? 2 : size / 2;
      const int mids = size - corners;
      for (int k = 0; k < mids; ++k) {
        auto node = [&](int i) {
          return meshtest::position(mesh_, group.facets.nodes[static_cast<std::size_t>(first + i)]);
        };
        const auto a = node(k);
        const auto b = node((k + 1) % corners);
        const auto m = node(corners + k);
        for (int x = 0; x < 3; ++x) ASSERT_NEAR(m[x], 0.5 * (a[x] + b[x]), 1e-9) << group.name << " facet " << f;
      }
    }
}

/// Boundary groups lie on their plane: group -> (axis, value).
TEST_P(GmshFile, BoundaryGroupsLieOnTheirPlanes) {
  const std::map<std::string, std::pair<int, double>> planes{
      {"clamp", {0, 0.0}}, {"tip", {0, 1.0}}, {"load", {1, 2.0}}, {"bottom", {2, 0.0}}, {"top", {2, 1.0}}};
  for (const tensormass::Group& group : mesh_.groups) {
    const auto plane = planes.find(group.name);
    if (plane == planes.end()) continue;
    for (int node : group.nodes)
      EXPECT_NEAR(meshtest::position(mesh_, node)[static_cast<std::size_t>(plane->second.first)], plane->second.second,
                  1e-12)
          << group.name;
  }
}

TEST_P(GmshFile, VolumeGroupsListTheirCells) {
  for (const tensormass::Group& group : mesh_.groups) {
    if (group.dim != mesh_.dim) continue;
    for (int cell : group.cells) {
      const auto [b, local] = mesh_.locate(cell);
      for (int node : mesh_.blocks[static_cast<std::size_t>(b)].cell_nodes(local))
        EXPECT_TRUE(std::binary_search(group.nodes.begin(), group.nodes.end(), node)) << group.name;
    }
  }
}

std::string case_name(const testing::TestParamInfo<Case>& info) { return info.param.stem + "_" + info.param.encoding; }

INSTANTIATE_TEST_SUITE_P(Meshes, GmshFile, testing::ValuesIn(all_cases()), case_name);

class GmshEncodings : public testing::TestWithParam<std::string> {};

TEST_P(GmshEncodings, AllFourEncodingsGiveIdenticalMeshes) {
  const Mesh ascii22 = tensormass::read_mesh(file_of(GetParam(), "msh22"));
  const Mesh binary22 = tensormass::read_mesh(file_of(GetParam(), "msh22b"));
  const Mesh ascii41 = tensormass::read_mesh(file_of(GetParam(), "msh41"));
  const Mesh binary41 = tensormass::read_mesh(file_of(GetParam(), "msh41b"));
  meshtest::expect_identical(ascii22, binary22, true);
  meshtest::expect_identical(ascii41, binary41, true);
  // MSH 2.2 numbers an element once per physical group: element ids differ from 4.1.
  meshtest::expect_identical(ascii22, ascii41, false);
}

INSTANTIATE_TEST_SUITE_P(Meshes, GmshEncodings, testing::ValuesIn(stems()));

TEST(GmshReader, UnnamedPhysicalGroupIsNamedByItsNumber) {
  const Mesh mesh = tensormass::read_mesh(file_of("box_tet_o1", "msh41"));
  const tensormass::Group* point = mesh.group("7");
  ASSERT_NE(point, nullptr);
  EXPECT_EQ(point->dim, 0);
  EXPECT_EQ(point->nodes.size(), 1u);
  const tensormass::Group* edge = mesh.group("edge");
  ASSERT_NE(edge, nullptr);
  EXPECT_EQ(edge->dim, 1);
  EXPECT_EQ(edge->facets.count(), 0);
}

TEST(GmshReader, SourceIdsAreTheFileNumbers) {
  const Mesh mesh = tensormass::read_mesh(file_of("box_hex_o1", "msh41"));
  EXPECT_EQ(mesh.source, file_of("box_hex_o1", "msh41"));
  ASSERT_EQ(mesh.node_source_ids.size(), 36u);
  EXPECT_EQ(mesh.node_source_ids.front(), 1);
  EXPECT_EQ(mesh.blocks.front().source_ids.size(), 12u);
  EXPECT_NE(mesh.describe_cell(0).find("box_hex_o1.msh41.msh"), std::string::npos);
}

// A hand-written MSH 2.2 file as Gmsh writes an element in two physical
// groups: twice, with different ids. One cell results, in both groups.
TEST(GmshReader, Msh22DuplicatesOfAnElementInSeveralGroupsAreMerged) {
  test_support::TempDir dir;
  const std::string path = dir.write("dup.msh",
                                     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                                     "$PhysicalNames\n2\n2 10 \"a\"\n2 11 \"b\"\n$EndPhysicalNames\n"
                                     "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n"
                                     "$Elements\n4\n1 2 2 10 1 1 2 3\n2 2 2 11 1 1 2 3\n3 2 2 10 1 1 3 4\n"
                                     "4 15 2 12 1 1\n$EndElements\n");
  const Mesh mesh = tensormass::read_mesh(path);
  EXPECT_EQ(mesh.dim, 2);
  EXPECT_EQ(mesh.cell_count(), 2);
  ASSERT_NE(mesh.group("a"), nullptr);
  ASSERT_NE(mesh.group("b"), nullptr);
  ASSERT_NE(mesh.group("12"), nullptr);
  EXPECT_EQ(mesh.group("a")->cells, (std::vector<int>{0, 1}));
  EXPECT_EQ(mesh.group("b")->cells, (std::vector<int>{0}));
  EXPECT_EQ(mesh.group("12")->nodes, (std::vector<int>{0}));
  EXPECT_EQ(mesh.blocks[0].source_ids, (std::vector<long>{1, 3}));
}

// Nodes used by no cell are dropped; file ids stay in node_source_ids.
TEST(GmshReader, UnusedNodesAreDroppedAndIdsKept) {
  test_support::TempDir dir;
  const std::string path = dir.write("sparse.msh",
                                     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                                     "$Nodes\n5\n10 0 0 0\n20 1 0 0\n999 5 5 5\n30 0 1 0\n1000000 0 0 1\n$EndNodes\n"
                                     "$Elements\n1\n7 4 0 10 20 30 1000000\n$EndElements\n");
  const Mesh mesh = tensormass::read_mesh(path);
  EXPECT_EQ(mesh.node_count(), 4);
  EXPECT_EQ(mesh.node_source_ids, (std::vector<long>{10, 20, 30, 1000000}));
  EXPECT_EQ(mesh.blocks[0].connectivity, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_TRUE(mesh.groups.empty());
}

TEST(GmshReader, UnknownSectionsAreSkipped) {
  test_support::TempDir dir;
  const std::string path = dir.write("extra.msh",
                                     "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                                     "$Comments\nanything $Nodes here\n$EndComments\n"
                                     "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"
                                     "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n"
                                     "$NodeData\n1\n\"u\"\n1\n0.0\n3\n0\n1\n4\n1 0\n2 0\n3 0\n4 0\n$EndNodeData\n");
  const Mesh mesh = tensormass::read_mesh(path);
  EXPECT_EQ(mesh.cell_count(), 1);
  EXPECT_EQ(mesh.node_count(), 4);
}

// MSH 4.1 node blocks with parametric coordinates (u on curves, u v on surfaces).
TEST(GmshReader, Msh41ParametricNodesAreRead) {
  test_support::TempDir dir;
  const std::string path = dir.write("param.msh",
                                     "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                                     "$Nodes\n3 4 1 4\n0 1 1 1\n1\n0 0 0\n1 1 1 1\n2\n1 0 0 0.5\n"
                                     "2 1 1 2\n3\n4\n0 1 0 0.1 0.2\n0 0 1 0.3 0.4\n$EndNodes\n"
                                     "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n");
  const Mesh mesh = tensormass::read_mesh(path);
  EXPECT_EQ(mesh.rest_positions, (std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}));
}

// A big-endian binary MSH 2.2 file (as a big-endian machine writes it).
TEST(GmshReader, BigEndianBinaryMsh22) {
  auto be32 = [](std::int32_t v) {
    std::string s(4, '\0');
    for (int i = 0; i < 4; ++i)
      s[static_cast<std::size_t>(i)] = static_cast<char>((static_cast<std::uint32_t>(v) >> (24 - 8 * i)) & 0xff);
    return s;
  };
  auto be64 = [](double x) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, 8);
    std::string s(8, '\0');
    for (int i = 0; i < 8; ++i) s[static_cast<std::size_t>(i)] = static_cast<char>((bits >> (56 - 8 * i)) & 0xff);
    return s;
  };
  std::string text = "$MeshFormat\n2.2 1 8\n" + be32(1) + "\n$EndMeshFormat\n$Nodes\n4\n";
  const double xyz[4][3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}};
  for (int n = 0; n < 4; ++n) text += be32(n + 1) + be64(xyz[n][0]) + be64(xyz[n][1]) + be64(xyz[n][2]);
  text += "\n$EndNodes\n$Elements\n1\n" + be32(4) + be32(1) + be32(2) + be32(1) + be32(5) + be32(9) + be32(1) +
          be32(2) + be32(3) + be32(4) + "\n$EndElements\n";
  test_support::TempDir dir;
  const Mesh mesh = tensormass::read_mesh(dir.write("be.msh", text));
  ASSERT_EQ(mesh.cell_count(), 1);
  EXPECT_EQ(mesh.rest_positions[3], 2.0);
  ASSERT_NE(mesh.group("5"), nullptr);
  const std::vector<double> cell = tensormass::cell_coordinates(mesh, mesh.blocks[0], 0);
  EXPECT_NEAR(tensormass::cell_volume(*mesh.blocks[0].element, 3, cell), 8.0 / 6.0, 1e-14);
}

// Node ids are any 64-bit values: the span of the smallest and largest
// overflows a signed difference, so the index takes the ids as they are.
TEST(GmshReader, NodeIdsOfAnySixtyFourBitValueAreRead) {
  const long lowest = std::numeric_limits<long>::min();
  const long highest = std::numeric_limits<long>::max();
  test_support::TempDir dir;
  const std::string path = dir.write(
      "extreme_ids.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n" + std::to_string(lowest) + " 0 0 0\n" +
                             std::to_string(highest) + " 1 0 0\n2 0 1 0\n3 0 0 1\n$EndNodes\n$Elements\n1\n1 4 2 1 1 " +
                             std::to_string(lowest) + " " + std::to_string(highest) + " 2 3\n$EndElements\n");
  const Mesh mesh = tensormass::read_mesh(path);
  EXPECT_EQ(mesh.node_source_ids, (std::vector<long>{lowest, highest, 2, 3}));
  EXPECT_EQ(mesh.blocks[0].connectivity, (std::vector<int>{0, 1, 2, 3}));
}

// Compact negative ids (a dense table) and an element naming the largest id,
// which the file does not define: refused, not looked up past the table.
TEST(GmshReader, AnUndefinedNodeIdFarFromTheOthersIsRefused) {
  test_support::TempDir dir;
  const std::string path =
      dir.write("far_id.msh",
                "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n-4 0 0 0\n-3 1 0 0\n-2 0 1 0\n-1 0 0 1\n"
                "$EndNodes\n$Elements\n1\n1 4 2 1 1 -4 -3 -2 " +
                    std::to_string(std::numeric_limits<long>::max()) + "\n$EndElements\n");
  meshtest::expect_input_error(path, {"far_id.msh:13", "refers to node 9223372036854775807", "does not define"});
}

// One entity with 2,000 physical tags and a block of 2,000 points in it: each
// point would be stored with all 2,000 groups (4 million entries from a 20 kB
// file), so the memberships are bounded by the file's size.
TEST(GmshReader, GroupMembershipsBeyondTheFileSizeAreRefused) {
  std::string tags;
  for (int t = 1; t <= 2000; ++t) tags += " " + std::to_string(t);
  std::string points;
  for (int p = 1; p <= 2000; ++p) points += std::to_string(p) + " 1\n";
  test_support::TempDir dir;
  const std::string path = dir.write("memberships.msh",
                                     "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                                     "$Entities\n1 0 0 0\n1 0 0 0 2000" +
                                         tags +
                                         "\n$EndEntities\n"
                                         "$Nodes\n1 1 1 1\n0 1 0 1\n1\n0 0 0\n$EndNodes\n"
                                         "$Elements\n1 2000 1 2000\n0 1 15 2000\n" +
                                         points + "$EndElements\n");
  meshtest::expect_input_error(path, {"memberships.msh:", "physical groups in all"});
}

}  // namespace
