// VTU reader (.vtu): files written by meshio (tests/data/meshes) read to
// the same mesh as the Gmsh file they came from; every DataArray encoding
// (ascii, inline base64 with the header encoded with or apart from the
// data, appended raw and base64, UInt32 and UInt64 headers, big-endian) on
// files written here; several pieces, many pieces in linear time, and
// arrays sharing appended data refused by their total size.
#include <gtest/gtest.h>

#include <algorithm>
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

class MeshioVtuFile : public testing::TestWithParam<std::string> {};

TEST_P(MeshioVtuFile, ReadsToTheSameMeshAsTheGmshFile) {
  const std::string& file = GetParam();
  meshtest::expect_same_mesh_as_gmsh(file, file.substr(0, file.find('.')));
}

INSTANTIATE_TEST_SUITE_P(Meshio, MeshioVtuFile,
                         testing::Values("box_tet_o2.ascii.vtu", "hybrid_o1.b64.vtu", "plate2d_o1.b64u64.vtu"),
                         [](const testing::TestParamInfo<std::string>& info) {
                           return meshtest::test_name_of(info.param);
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
