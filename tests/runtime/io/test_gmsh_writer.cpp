// write_msh: the Gmsh Python API and meshio read our files with the right
// nodes, cells, groups and orientation; read_mesh reads them back unchanged.
#include <gtest/gtest.h>

#include <map>
#include <sstream>

#include "support/python_check.hpp"
#include "support/test_meshes.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/gmsh_writer.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/meshing/beam.hpp"

namespace {

using tensormass::Mesh;
using tensormass::io::MshFormat;

struct MshCase {
  std::string name;
  int dim;
  std::array<int, 3> cells;
  std::string mix;
  int order;
  MshFormat format;
};

void PrintTo(const MshCase& c, std::ostream* out) { *out << c.name; }

Mesh beam(const MshCase& c) {
  tensormass::BeamSpec spec;
  spec.dim = c.dim;
  spec.cells = c.cells;
  spec.size = {1.0, 0.3, 0.7};
  spec.phases = tensormass::parse_beam_mix(c.mix);
  spec.order = c.order;
  return tensormass::make_beam(spec);
}

std::vector<MshCase> cases() {
  std::vector<MshCase> all;
  for (MshFormat format : {MshFormat::v41, MshFormat::v22}) {
    const std::string v = format == MshFormat::v41 ? "_v41" : "_v22";
    all.push_back({"quad4" + v, 2, {6, 2, 1}, "quad4:1", 1, format});
    all.push_back({"tri3_quad4" + v, 2, {10, 2, 1}, "tri3:0.3,quad4:0.7", 1, format});
    all.push_back({"tri6_quad8" + v, 2, {4, 2, 1}, "tri3:0.5,quad4:0.5", 2, format});
    all.push_back({"hex8_tet5" + v, 3, {4, 2, 2}, "hex8:0.5,tet5:0.5", 1, format});
    all.push_back({"four_phases" + v, 3, {8, 2, 2}, "tet6:0.25,pyramid5:0.25,prism6:0.25,hex8:0.25", 1, format});
    all.push_back({"hex20" + v, 3, {2, 2, 1}, "hex8:1", 2, format});
    all.push_back({"tet10" + v, 3, {4, 1, 2}, "tet5:0.5,tet6:0.5", 2, format});
  }
  return all;
}

class MshWriterTest : public testing::TestWithParam<MshCase> {};

TEST_P(MshWriterTest, GmshAndMeshioReadNodesCellsGroupsAndOrientation) {
  const test_support::TempDir dir;
  const Mesh mesh = beam(GetParam());
  tensormass::io::write_msh(dir.file("beam.msh"), mesh, GetParam().format);
  dir.write("expected.json", tmtest::msh_expectation(mesh));
  EXPECT_EQ(tmtest::run_check("check_msh.py", dir.file("beam.msh"), dir.file("expected.json")), 0);
}

/// Cells and facets compared through their node lists (files may reorder elements).
std::map<std::vector<int>, std::vector<int>> cells_by_node_set(const Mesh& mesh) {
  std::map<std::vector<int>, std::vector<int>> cells;
  for (const tensormass::ElementBlock& block : mesh.blocks)
    for (int local = 0; local < block.count(); ++local) {
      const std::span<const int> nodes = block.cell_nodes(local);
      std::vector<int> key(nodes.begin(), nodes.end());
      std::sort(key.begin(), key.end());
      cells[key] = {nodes.begin(), nodes.end()};
    }
  return cells;
}

std::vector<std::vector<int>> group_cell_nodes(const Mesh& mesh, const tensormass::Group& group) {
  std::vector<std::vector<int>> cells;
  for (int cell : group.cells) {
    const auto [b, local] = mesh.locate(cell);
    const std::span<const int> nodes = mesh.blocks[b].cell_nodes(local);
    cells.emplace_back(nodes.begin(), nodes.end());
  }
  std::sort(cells.begin(), cells.end());
  return cells;
}

TEST_P(MshWriterTest, ReadMeshReadsItBackUnchanged) {
  const test_support::TempDir dir;
  const Mesh mesh = beam(GetParam());
  tensormass::io::write_msh(dir.file("beam.msh"), mesh, GetParam().format);
  const Mesh back = tensormass::read_mesh(dir.file("beam.msh"));
  EXPECT_EQ(back.dim, mesh.dim);
  EXPECT_EQ(back.rest_positions, mesh.rest_positions);
  EXPECT_EQ(meshtest::cells_per_type(back), meshtest::cells_per_type(mesh));
  EXPECT_EQ(cells_by_node_set(back), cells_by_node_set(mesh)) << "cells differ (node order included)";
  ASSERT_EQ(back.groups.size(), mesh.groups.size());
  for (const tensormass::Group& group : mesh.groups) {
    const tensormass::Group* read = back.group(group.name);
    ASSERT_NE(read, nullptr) << group.name;
    EXPECT_EQ(read->dim, group.dim) << group.name;
    EXPECT_EQ(read->nodes, group.nodes) << group.name;
    EXPECT_EQ(read->facets.count(), group.facets.count()) << group.name;
    EXPECT_EQ(group_cell_nodes(back, *read), group_cell_nodes(mesh, group)) << group.name;
  }
}

INSTANTIATE_TEST_SUITE_P(Beams, MshWriterTest, testing::ValuesIn(cases()),
                         [](const testing::TestParamInfo<MshCase>& info) { return info.param.name; });

TEST(MshWriter, CoordinatesAreExact) {
  const test_support::TempDir dir;
  Mesh mesh = beam({"", 3, {3, 1, 1}, "hex8:1", 1, MshFormat::v41});
  for (std::size_t i = 0; i < mesh.rest_positions.size(); ++i)
    mesh.rest_positions[i] += (i % 2 ? 1.0 : -1.0) * 1e-9 / (3.0 + static_cast<double>(i));
  for (MshFormat format : {MshFormat::v41, MshFormat::v22}) {
    tensormass::io::write_msh(dir.file("exact.msh"), mesh, format);
    dir.write("expected.json", tmtest::msh_expectation(mesh));
    EXPECT_EQ(tmtest::run_check("check_msh.py", dir.file("exact.msh"), dir.file("expected.json")), 0);
  }
}

TEST(MshWriter, NodeOnlyGroupsBecomePointElements) {
  const test_support::TempDir dir;
  Mesh mesh = beam({"", 2, {3, 1, 1}, "quad4:1", 1, MshFormat::v41});
  tensormass::Group probe;
  probe.name = "probe";
  probe.dim = 0;
  probe.nodes = {1, 6};
  mesh.groups.push_back(probe);
  for (MshFormat format : {MshFormat::v41, MshFormat::v22}) {
    tensormass::io::write_msh(dir.file("points.msh"), mesh, format);
    dir.write("expected.json", tmtest::msh_expectation(mesh));
    EXPECT_EQ(tmtest::run_check("check_msh.py", dir.file("points.msh"), dir.file("expected.json")), 0);
    const Mesh back = tensormass::read_mesh(dir.file("points.msh"));
    ASSERT_NE(back.group("probe"), nullptr);
    EXPECT_EQ(back.group("probe")->nodes, probe.nodes);
  }
}

TEST(MshWriter, Format41WritesACellInSeveralGroupsOnce) {
  const test_support::TempDir dir;
  const Mesh mesh = beam({"", 2, {10, 2, 1}, "tri3:0.3,quad4:0.7", 1, MshFormat::v41});
  tensormass::io::write_msh(dir.file("a.msh"), mesh, MshFormat::v41);
  const std::string text = test_support::read_file(dir.file("a.msh"));
  EXPECT_EQ(text.rfind("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n", 0), 0u);
  const int elements = mesh.cell_count() + mesh.group("clamp")->facets.count() + mesh.group("tip")->facets.count();
  const std::string header = "$Elements\n";
  const std::size_t at = text.find(header);
  ASSERT_NE(at, std::string::npos);
  std::istringstream line(text.substr(at + header.size()));
  long blocks = 0, count = 0;
  line >> blocks >> count;
  EXPECT_EQ(count, elements);
}

TEST(MshWriter, Format22StartsWithItsHeader) {
  const test_support::TempDir dir;
  tensormass::io::write_msh(dir.file("a.msh"), beam({"", 2, {2, 1, 1}, "quad4:1", 1, MshFormat::v22}), MshFormat::v22);
  EXPECT_EQ(test_support::read_file(dir.file("a.msh")).rfind("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n", 0), 0u);
}

TEST(MshWriter, FormatNames) {
  EXPECT_EQ(tensormass::io::parse_msh_format("4.1"), MshFormat::v41);
  EXPECT_EQ(tensormass::io::parse_msh_format("2.2"), MshFormat::v22);
  EXPECT_THROW(tensormass::io::parse_msh_format("4.0"), tensormass::InputError);
}

TEST(MshWriter, UnwritablePathThrowsAndWritesNothing) {
  const test_support::TempDir dir;
  const Mesh mesh = beam({"", 2, {2, 1, 1}, "quad4:1", 1, MshFormat::v41});
  EXPECT_THROW(tensormass::io::write_msh(dir.file("missing/a.msh"), mesh), std::runtime_error);
  EXPECT_TRUE(dir.files().empty());
}

}  // namespace
