// VTK readers: files written by meshio (tests/data/meshes) read to the same
// mesh as the Gmsh file they came from; every VTU DataArray encoding
// (ascii, inline base64 with the header encoded with or apart from the
// data, appended raw and base64, UInt32 and UInt64 headers, big-endian) and
// the legacy keywords a reader meets (SCALARS/LOOKUP_TABLE, FIELD,
// POINT_DATA, METADATA) on files written here.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_meshes.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace {

using tensormass::Mesh;

struct Conversion {
  std::string vtk_file;
  std::string stem;
};

class MeshioFile : public testing::TestWithParam<Conversion> {};

TEST_P(MeshioFile, ReadsToTheSameMeshAsTheGmshFile) {
  const Mesh gmsh = tensormass::read_mesh(meshtest::data_file(GetParam().stem + ".msh41.msh"));
  const Mesh vtk = tensormass::read_mesh(meshtest::data_file(GetParam().vtk_file));
  meshtest::expect_same_cells(gmsh, vtk);
  const nlohmann::json& groups = meshtest::expected_meshes()[GetParam().stem]["groups"];
  ASSERT_EQ(vtk.groups.size(), groups.size());
  for (const auto& [name, expected] : groups.items()) {
    const tensormass::Group* from_gmsh = gmsh.group(name);
    const tensormass::Group* from_vtk = vtk.group("region_" + std::to_string(expected["tag"].get<int>()));
    ASSERT_NE(from_gmsh, nullptr);
    ASSERT_NE(from_vtk, nullptr) << name;
    EXPECT_EQ(from_vtk->dim, from_gmsh->dim) << name;
    EXPECT_EQ(from_vtk->cells, from_gmsh->cells) << name;
    EXPECT_EQ(from_vtk->facets.count(), from_gmsh->facets.count()) << name;
    EXPECT_EQ(meshtest::positions(vtk, from_vtk->nodes), meshtest::positions(gmsh, from_gmsh->nodes)) << name;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Meshio, MeshioFile,
    testing::Values(Conversion{"box_tet_o2.ascii.vtu", "box_tet_o2"}, Conversion{"hybrid_o1.b64.vtu", "hybrid_o1"},
                    Conversion{"plate2d_o1.b64u64.vtu", "plate2d_o1"}, Conversion{"box_hex_o2.v51.vtk", "box_hex_o2"},
                    Conversion{"box_tet_o1.v51b.vtk", "box_tet_o1"}, Conversion{"hybrid_o1.v42b.vtk", "hybrid_o1"},
                    Conversion{"plate2d_o2.v42.vtk", "plate2d_o2"}),
    [](const testing::TestParamInfo<Conversion>& info) {
      std::string name = info.param.vtk_file;
      for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return name;
    });

// --- A small VTU writer covering every encoding ---------------------------------

std::string base64(const std::string& bytes) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t chunk = 0;
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    for (std::size_t k = 0; k < 3; ++k) chunk = (chunk << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? alphabet[(chunk >> (18 - 6 * k)) & 63u] : '=';
  }
  return out;
}

template <class T>
std::string raw_bytes(const std::vector<T>& values, bool big_endian) {
  std::string out;
  for (const T& v : values) {
    char buffer[sizeof(T)];
    std::memcpy(buffer, &v, sizeof(T));
    if (big_endian) std::reverse(buffer, buffer + sizeof(T));
    out.append(buffer, sizeof(T));
  }
  return out;
}

struct VtuStyle {
  std::string format;            ///< ascii | binary | appended
  std::string encoding = "raw";  ///< appended: raw | base64
  bool header64 = false;
  bool separate_header = false;  ///< base64: header and data encoded apart (as VTK does)
  bool big_endian = false;
};

class VtuWriter {
 public:
  explicit VtuWriter(VtuStyle style) : style_(std::move(style)) {}

  template <class T>
  std::string array(const std::string& name, const std::string& type, int components, const std::vector<T>& values) {
    std::ostringstream tag;
    tag << "<DataArray type=\"" << type << "\" Name=\"" << name << "\" NumberOfComponents=\"" << components
        << "\" format=\"" << style_.format << "\"";
    if (style_.format == "ascii") {
      tag << ">\n";
      tag.precision(17);
      for (const T& v : values) tag << +v << " ";
      tag << "\n</DataArray>\n";
      return tag.str();
    }
    const std::string data = raw_bytes(values, style_.big_endian);
    const std::string header =
        style_.header64
            ? raw_bytes(std::vector<std::uint64_t>{data.size()}, style_.big_endian)
            : raw_bytes(std::vector<std::uint32_t>{static_cast<std::uint32_t>(data.size())}, style_.big_endian);
    const std::string encoded = style_.separate_header ? base64(header) + base64(data) : base64(header + data);
    if (style_.format == "binary") return tag.str() + ">" + encoded + "</DataArray>\n";
    tag << " offset=\"" << appended_.size() << "\"/>\n";
    appended_ += style_.encoding == "raw" ? header + data : encoded;
    return tag.str();
  }

  std::string file(const Mesh& mesh) {
    std::vector<double> points = mesh.rest_positions;
    std::vector<std::int64_t> connectivity;
    std::vector<std::int64_t> offsets;
    std::vector<std::uint8_t> types;
    std::vector<std::int32_t> regions;
    for (const tensormass::ElementBlock& block : mesh.blocks)
      for (int c = 0; c < block.count(); ++c) {
        for (int node : block.cell_nodes(c)) connectivity.push_back(node);
        offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
        types.push_back(static_cast<std::uint8_t>(block.element->vtk_type));
        regions.push_back(block.first_cell + c < 3 ? 7 : 8);
      }
    std::string body = "<Piece NumberOfPoints=\"" + std::to_string(mesh.node_count()) + "\" NumberOfCells=\"" +
                       std::to_string(mesh.cell_count()) + "\">\n<Points>\n" + array("Points", "Float64", 3, points) +
                       "</Points>\n<Cells>\n" + array("connectivity", "Int64", 1, connectivity) +
                       array("offsets", "Int64", 1, offsets) + array("types", "UInt8", 1, types) + "</Cells>\n" +
                       "<CellData>\n" + array("region", "Int32", 1, regions) + "</CellData>\n</Piece>\n";
    std::string text =
        "<?xml version=\"1.0\"?>\n<!-- written by the tensormass tests -->\n"
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"" +
        std::string(style_.big_endian ? "BigEndian" : "LittleEndian") + "\" header_type=\"" +
        (style_.header64 ? "UInt64" : "UInt32") + "\">\n<UnstructuredGrid>\n" + body + "</UnstructuredGrid>\n";
    if (style_.format == "appended")
      text += "<AppendedData encoding=\"" + style_.encoding + "\">\n_" + appended_ + "\n</AppendedData>\n";
    return text + "</VTKFile>\n";
  }

 private:
  VtuStyle style_;
  std::string appended_;
};

class VtuEncoding : public testing::TestWithParam<VtuStyle> {};

TEST_P(VtuEncoding, ReadsBackTheMeshItWasWrittenFrom) {
  const Mesh source = tensormass::read_mesh(meshtest::data_file("hybrid_o1.msh41.msh"));
  test_support::TempDir dir;
  const std::string path = dir.write("mesh.vtu", VtuWriter(GetParam()).file(source));
  const Mesh mesh = tensormass::read_mesh(path);
  meshtest::expect_same_cells(source, mesh);
  EXPECT_EQ(mesh.rest_positions, source.rest_positions);
  ASSERT_EQ(mesh.groups.size(), 2u);
  EXPECT_EQ(mesh.groups[0].name, "region_7");
  EXPECT_EQ(mesh.groups[0].cells, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(mesh.groups[1].name, "region_8");
  EXPECT_EQ(mesh.groups[1].dim, 3);
}

INSTANTIATE_TEST_SUITE_P(
    Styles, VtuEncoding,
    testing::Values(VtuStyle{"ascii"}, VtuStyle{"binary", "raw", false, false}, VtuStyle{"binary", "raw", true, false},
                    VtuStyle{"binary", "raw", false, true}, VtuStyle{"binary", "raw", true, true},
                    VtuStyle{"appended", "raw", false}, VtuStyle{"appended", "raw", true},
                    VtuStyle{"appended", "base64", false, false}, VtuStyle{"appended", "base64", true, true},
                    VtuStyle{"appended", "raw", true, false, true}, VtuStyle{"binary", "raw", false, true, true}));

TEST(VtuReader, SeveralPiecesAreConcatenated) {
  const std::string piece =
      "<Piece NumberOfPoints=\"3\" NumberOfCells=\"1\">\n"
      "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 0 1 "
      "0</DataArray></Points>\n"
      "<Cells><DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2</DataArray>\n"
      "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">3</DataArray>\n"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">5</DataArray></Cells>\n</Piece>\n";
  test_support::TempDir dir;
  const std::string path = dir.write("pieces.vtu", "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid>" + piece +
                                                       piece + "</UnstructuredGrid></VTKFile>");
  const Mesh mesh = tensormass::read_mesh(path);
  EXPECT_EQ(mesh.dim, 2);
  EXPECT_EQ(mesh.node_count(), 6);
  EXPECT_EQ(mesh.blocks[0].connectivity, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_TRUE(mesh.groups.empty());
}

// Classic legacy layout with SCALARS + LOOKUP_TABLE, POINT_DATA to skip,
// a VTK 9 METADATA block and a "group" array when no gmsh:physical exists.
TEST(LegacyVtkReader, AttributesAreSkippedAndScalarsMakeGroups) {
  test_support::TempDir dir;
  const std::string path = dir.write("legacy.vtk",
                                     "# vtk DataFile Version 3.0\nhand written\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                                     "FIELD FieldData 1\nTIME 1 1 double\n0.5\n"
                                     "POINTS 5 float\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n"
                                     "METADATA\nINFORMATION 0\n\n"
                                     "CELLS 3 11\n4 0 1 2 3\n1 4\n3 0 1 2\n"
                                     "CELL_TYPES 3\n10\n1\n5\n"
                                     "POINT_DATA 5\nVECTORS u double\n0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n"
                                     "CELL_DATA 3\nSCALARS group int 1\nLOOKUP_TABLE default\n4\n9\n4\n"
                                     "SCALARS quality double\nLOOKUP_TABLE default\n1.5\n2.5\n3.5\n");
  // The vertex (point 4) lies on no tetrahedron: its group cannot be built.
  meshtest::expect_input_error(path, {"legacy.vtk:", "cell 1 (point)", "node 4", "belongs to no 3D element"});
  const std::string fixed = dir.write(
      "legacy2.vtk", test_support::read_file(path).replace(test_support::read_file(path).find("1 4\n"), 4, "1 3\n"));
  const Mesh mesh = tensormass::read_mesh(fixed);
  EXPECT_EQ(mesh.cell_count(), 1);
  ASSERT_EQ(mesh.groups.size(), 2u);
  EXPECT_EQ(mesh.groups[0].name, "region_4");
  EXPECT_EQ(mesh.groups[0].cells, (std::vector<int>{0}));
  EXPECT_EQ(mesh.groups[0].facets.count(), 1);
  EXPECT_EQ(mesh.groups[1].name, "region_9");
  EXPECT_EQ(mesh.groups[1].dim, 0);
  EXPECT_EQ(mesh.groups[1].nodes, (std::vector<int>{3}));
}

/// A VTU of `empty_pieces` pieces without points or cells, then one triangle.
std::string many_pieces_vtu(int empty_pieces) {
  const std::string empty =
      "<Piece NumberOfPoints=\"0\" NumberOfCells=\"0\"><Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" "
      "format=\"ascii\"></DataArray></Points><Cells><DataArray type=\"Int64\" Name=\"connectivity\" "
      "format=\"ascii\"></DataArray><DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\"></DataArray>"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\"></DataArray></Cells></Piece>\n";
  const std::string triangle =
      "<Piece NumberOfPoints=\"3\" NumberOfCells=\"1\"><Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" "
      "format=\"ascii\">0 0 0 1 0 0 0 1 0</DataArray></Points><Cells><DataArray type=\"Int64\" Name=\"connectivity\" "
      "format=\"ascii\">0 1 2</DataArray><DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">3</DataArray>"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">5</DataArray></Cells></Piece>\n";
  std::string text = "<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n";
  text.reserve(text.size() + static_cast<std::size_t>(empty_pieces) * empty.size() + 1000);
  for (int p = 0; p < empty_pieces; ++p) text += empty;
  return text + triangle + "</UnstructuredGrid>\n</VTKFile>\n";
}

// Elements are found among their parent's children and lines are counted
// once: 12,000 pieces (4 MB) read in well under a second, where a lookup
// over all elements per piece took minutes.
TEST(VtuReader, ManyPiecesReadInLinearTime) {
  test_support::TempDir dir;
  const std::string path = dir.write("many_pieces.vtu", many_pieces_vtu(12000));
  const auto start = std::chrono::steady_clock::now();
  const Mesh mesh = tensormass::read_mesh(path);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(mesh.cell_count(), 1);
  EXPECT_EQ(mesh.node_count(), 3);
  EXPECT_LT(seconds, 10.0);
}

// 50 pieces whose offsets, types and regions all point at one appended
// block of 20,000 bytes: each array alone fits in the file, their sum does
// not, and the reader refuses before decoding them all.
TEST(VtuReader, ArraysSharingAppendedDataAreRefusedByTheirTotalSize) {
  const std::size_t block = 20000;
  std::string pieces;
  for (int p = 0; p < 50; ++p)
    pieces += "<Piece NumberOfPoints=\"0\" NumberOfCells=\"" + std::to_string(block) +
              "\"><Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\"></DataArray>"
              "</Points><Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\"></DataArray>"
              "<DataArray type=\"UInt8\" Name=\"offsets\" format=\"appended\" offset=\"0\"/>"
              "<DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"0\"/></Cells>"
              "<CellData><DataArray type=\"UInt8\" Name=\"region\" format=\"appended\" offset=\"0\"/></CellData>"
              "</Piece>\n";
  std::string header(8, '\0');
  for (int i = 0; i < 8; ++i) header[static_cast<std::size_t>(i)] = static_cast<char>((block >> (8 * i)) & 0xff);
  test_support::TempDir dir;
  const std::string path =
      dir.write("shared.vtu", "<VTKFile type=\"UnstructuredGrid\" header_type=\"UInt64\">\n<UnstructuredGrid>\n" +
                                  pieces + "</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_" + header +
                                  std::string(block, '\0') + "\n</AppendedData>\n</VTKFile>\n");
  meshtest::expect_input_error(path, {"shared.vtu: byte", "more data in total than the file"});
}

}  // namespace
