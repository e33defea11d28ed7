// write_vtu / write_pvd: meshio reads back exact positions, cells, point and cell data.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "support/python_check.hpp"
#include "tensormass/io/vtk_writer.hpp"
#include "tensormass/meshing/beam.hpp"

namespace {

using tensormass::Mesh;
using tensormass::io::Field;

Mesh beam(int dim, const std::string& mix, int order, std::array<int, 3> cells) {
  tensormass::BeamSpec spec;
  spec.dim = dim;
  spec.cells = cells;
  spec.size = {1.0, 1.0 / 3.0, 0.7};
  spec.phases = tensormass::parse_beam_mix(mix);
  spec.order = order;
  return tensormass::make_beam(spec);
}

/// Values with full 17-digit mantissas, and a few extremes.
std::vector<double> awkward_values(std::size_t count, double seed) {
  std::vector<double> values(count);
  for (std::size_t i = 0; i < count; ++i)
    values[i] = std::sin(seed + 0.7 * i) / 3.0 * std::pow(10.0, static_cast<int>(i % 7) - 3);
  if (count > 2) {
    values[0] = 1e-300;
    values[1] = -0.0;
  }
  return values;
}

std::string field_json(const std::vector<Field>& fields) {
  std::string json = "{";
  for (std::size_t f = 0; f < fields.size(); ++f)
    json += (f ? ",\"" : "\"") + fields[f].name + "\":{\"components\":" + std::to_string(fields[f].components) +
            ",\"values\":" + tmtest::json_list(fields[f].values) + "}";
  return json + "}";
}

/// check_vtu.py's expectation: positions = rest + displacement, VTK connectivity, data.
std::string vtu_expectation(const Mesh& mesh, const std::vector<double>& displacement,
                            const std::vector<Field>& point_data, const std::vector<Field>& cell_data) {
  std::vector<double> points = mesh.rest_positions;
  for (std::size_t i = 0; i < displacement.size(); ++i) points[i] += displacement[i];
  std::vector<int> types;
  std::string connectivity = "[";
  for (const tensormass::ElementBlock& block : mesh.blocks)
    for (int local = 0; local < block.count(); ++local) {
      std::vector<int> vtk;
      for (int k = 0; k < block.element->nodes; ++k)
        vtk.push_back(block.cell_nodes(local)[block.element->vtk_order[k]]);
      connectivity += (types.empty() ? "" : ",") + tmtest::json_list(vtk);
      types.push_back(block.element->vtk_type);
    }
  return "{\"points\":" + tmtest::json_list(points) + ",\"cell_types\":" + tmtest::json_list(types) +
         ",\"connectivity\":" + connectivity + "],\"point_data\":" + field_json(point_data) +
         ",\"cell_data\":" + field_json(cell_data) + "}";
}

void expect_meshio_reads_back(const Mesh& mesh, bool displaced) {
  const test_support::TempDir dir;
  const std::size_t n = mesh.node_count(), cells = mesh.cell_count();
  const std::vector<double> displacement = displaced ? awkward_values(3 * n, 0.1) : std::vector<double>{};
  const std::vector<Field> point_data{{"displacement", 3, awkward_values(3 * n, 0.2)},
                                      {"temperature", 1, awkward_values(n, 0.3)}};
  std::vector<double> law_id(cells);
  for (std::size_t c = 0; c < cells; ++c) law_id[c] = static_cast<double>(c % 3);
  const std::vector<Field> cell_data{{"law_id", 1, law_id}, {"R_EL & <R_V>", 2, awkward_values(2 * cells, 0.4)}};
  tensormass::io::write_vtu(dir.file("mesh.vtu"), mesh, displacement, point_data, cell_data);
  dir.write("expected.json", vtu_expectation(mesh, displacement, point_data, cell_data));
  EXPECT_EQ(tmtest::run_check("check_vtu.py", dir.file("mesh.vtu"), dir.file("expected.json")), 0);
  EXPECT_EQ(dir.files(), (std::vector<std::string>{"expected.json", "mesh.vtu"}));
}

TEST(VtuWriter, MeshioReadsBackEveryLinearCellExactly) {
  expect_meshio_reads_back(beam(3, "tet5:0.25,hex8:0.25,prism6:0.25,pyramid5:0.25", 1, {8, 2, 2}), true);
}

TEST(VtuWriter, MeshioReadsBackQuadraticCells3D) {
  expect_meshio_reads_back(beam(3, "hex8:1", 2, {2, 2, 1}), true);
  expect_meshio_reads_back(beam(3, "tet6:1", 2, {2, 1, 1}), false);
}

TEST(VtuWriter, MeshioReadsBack2DMixes) {
  expect_meshio_reads_back(beam(2, "tri3:0.3,quad4:0.7", 1, {10, 3, 1}), true);
  expect_meshio_reads_back(beam(2, "tri3:0.5,quad4:0.5", 2, {4, 2, 1}), true);
}

TEST(VtuWriter, MeshioReadsArraysWhoseRewrittenOffsetsWouldCollide) {
  // meshio 5.0 rewrites each array's offset as it reads the data in order
  // and finds the next array by its offset. Two cells with cell fields of 4,
  // 1 and 1 components stored in tag order: the second field's rewritten
  // offset (96) is the third's raw offset, and meshio read the wrong arrays.
  const test_support::TempDir dir;
  const Mesh mesh = beam(2, "quad4:1", 1, {2, 1, 1});
  const std::vector<Field> cell_data{
      {"wide", 4, awkward_values(8, 0.5)}, {"global_cell", 1, {0.0, 1.0}}, {"law_id", 1, {2.0, 2.0}}};
  tensormass::io::write_vtu(dir.file("mesh.vtu"), mesh, {}, {}, cell_data);
  dir.write("expected.json", vtu_expectation(mesh, {}, {}, cell_data));
  EXPECT_EQ(tmtest::run_check("check_vtu.py", dir.file("mesh.vtu"), dir.file("expected.json")), 0);
}

TEST(VtuWriter, RejectsFieldsOfTheWrongSizeWithoutWriting) {
  const test_support::TempDir dir;
  const Mesh mesh = beam(2, "quad4:1", 1, {2, 1, 1});
  EXPECT_THROW(tensormass::io::write_vtu(dir.file("a.vtu"), mesh, {}, {{"u", 3, {1.0, 2.0}}}, {}),
               std::invalid_argument);
  EXPECT_THROW(tensormass::io::write_vtu(dir.file("a.vtu"), mesh, {}, {}, {{"law_id", 1, {1.0, 2.0, 3.0}}}),
               std::invalid_argument);
  EXPECT_THROW(tensormass::io::write_vtu(dir.file("a.vtu"), mesh, {1.0}, {}, {}), std::invalid_argument);
  EXPECT_TRUE(dir.files().empty());
}

TEST(VtuWriter, HeaderDeclaresVersion1WithUInt64RawAppendedData) {
  const test_support::TempDir dir;
  tensormass::io::write_vtu(dir.file("a.vtu"), beam(2, "quad4:1", 1, {2, 1, 1}), {}, {}, {});
  const std::string text = test_support::read_file(dir.file("a.vtu"));
  EXPECT_NE(text.find("version=\"1.0\""), std::string::npos);
  EXPECT_NE(text.find("header_type=\"UInt64\""), std::string::npos);
  EXPECT_NE(text.find("<AppendedData encoding=\"raw\">"), std::string::npos);
  EXPECT_NE(text.find("NumberOfPoints=\"6\" NumberOfCells=\"2\""), std::string::npos);
}

TEST(PvdWriter, ListsEveryFrameWithExactTimes) {
  const test_support::TempDir dir;
  tensormass::io::write_pvd(dir.file("series.pvd"),
                            {{0.0, "frame_000000.vtu"}, {0.1, "frame_000001.vtu"}, {1.0 / 3.0, "a&b.vtu"}});
  const std::string text = test_support::read_file(dir.file("series.pvd"));
  EXPECT_NE(text.find("<VTKFile type=\"Collection\""), std::string::npos);
  EXPECT_NE(text.find("<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"frame_000000.vtu\"/>"), std::string::npos);
  EXPECT_NE(text.find("timestep=\"0.1\""), std::string::npos);
  EXPECT_NE(text.find("timestep=\"0.3333333333333333\""), std::string::npos);
  EXPECT_NE(text.find("file=\"a&amp;b.vtu\""), std::string::npos);
  const test_support::Result parse =
      test_support::python("-c \"import xml.etree.ElementTree as E; r = E.parse('" + dir.file("series.pvd") +
                           "').getroot(); assert [d.get('file') for d in r.iter('DataSet')] == "
                           "['frame_000000.vtu', 'frame_000001.vtu', 'a&b.vtu']\"");
  EXPECT_EQ(parse.exit_code, 0) << parse.output;
}

}  // namespace
