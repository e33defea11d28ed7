// Bad mesh input: one test per class of error, each checking that
// read_mesh throws InputError naming the file and the line (or byte) and
// what is wrong; then truncated and corrupted copies of every committed
// mesh, which must be read or refused with InputError, never crash or hang.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "support/test_meshes.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace {

using meshtest::expect_input_error;
using test_support::TempDir;

// One tetrahedron, MSH 2.2 ASCII. Line numbers: 4 $Nodes, 5 count, 6..9
// nodes 1..4, 10 $EndNodes, 11 $Elements, 12 count, 13 the element.
std::string tet_msh(const std::string& node_lines = "1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n",
                    const std::string& element_line = "1 4 2 1 1 1 2 3 4\n", const std::string& node_count = "4") {
  return "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" + node_count + "\n" + node_lines +
         "$EndNodes\n$Elements\n1\n" + element_line + "$EndElements\n";
}

TEST(ReadMeshErrors, ValidReferenceFileReads) {
  TempDir dir;
  EXPECT_EQ(tensormass::read_mesh(dir.write("ok.msh", tet_msh())).cell_count(), 1);
}

TEST(ReadMeshErrors, MissingFile) {
  TempDir dir;
  expect_input_error(dir.file("nowhere.msh"), {"nowhere.msh", "cannot open"});
}

TEST(ReadMeshErrors, DirectoryInsteadOfFile) {
  TempDir dir;
  std::filesystem::create_directory(dir.file("folder.msh"));
  expect_input_error(dir.file("folder.msh"), {"folder.msh", "directory"});
}

TEST(ReadMeshErrors, UnknownExtension) {
  TempDir dir;
  expect_input_error(dir.write("mesh.obj", "v 0 0 0\n"), {"mesh.obj", ".obj"});
}

TEST(ReadMeshErrors, EmptyFiles) {
  TempDir dir;
  expect_input_error(dir.write("empty.msh", ""), {"empty.msh", "empty"});
  expect_input_error(dir.write("blank.vtu", " \n\n "), {"blank.vtu", "empty"});
  expect_input_error(dir.write("empty.vtk", ""), {"empty.vtk", "empty"});
}

TEST(ReadMeshErrors, NotAGmshFile) {
  TempDir dir;
  expect_input_error(dir.write("text.msh", "hello world\n"), {"text.msh:1:", "$MeshFormat"});
}

TEST(ReadMeshErrors, UnsupportedMshVersion) {
  TempDir dir;
  expect_input_error(dir.write("v4.msh", "$MeshFormat\n4.0 0 8\n$EndMeshFormat\n"),
                     {"v4.msh:2:", "4.0", "not supported"});
}

TEST(ReadMeshErrors, TruncatedAsciiFile) {
  TempDir dir;
  const std::string text = tet_msh();
  expect_input_error(dir.write("cut.msh", text.substr(0, text.find("1 4 2 1 1 1 2") + 13)),
                     {"cut.msh:13:", "truncated"});
  expect_input_error(dir.write("cut_nodes.msh", text.substr(0, text.find("3 0 1 0") + 3)),
                     {"cut_nodes.msh:5:", "truncated"});
}

TEST(ReadMeshErrors, MissingEndMarker) {
  TempDir dir;
  std::string text = tet_msh();
  text.erase(text.find("$EndNodes"), 10);
  expect_input_error(dir.write("noend.msh", text), {"noend.msh:10:", "$EndNodes", "$Elements"});
}

TEST(ReadMeshErrors, GarbledNumber) {
  TempDir dir;
  expect_input_error(dir.write("garbled.msh", tet_msh("1 0 0 0\n2 1 0x 0\n3 0 1 0\n4 0 0 1\n")),
                     {"garbled.msh:7:", "'0x'", "expected a number"});
  expect_input_error(dir.write("garbled_id.msh", tet_msh("1 0 0 0\n2.5 1 0 0\n3 0 1 0\n4 0 0 1\n")),
                     {"garbled_id.msh:7:", "'2.5'", "integer"});
}

TEST(ReadMeshErrors, NodeIndexOutOfRange) {
  TempDir dir;
  expect_input_error(dir.write("range.msh", tet_msh("1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n", "57 4 2 1 1 1 2 3 99\n")),
                     {"range.msh:13:", "element 57", "node 99"});
}

TEST(ReadMeshErrors, NonFiniteCoordinates) {
  TempDir dir;
  expect_input_error(dir.write("nan.msh", tet_msh("1 0 0 0\n2 1 0 0\n3 nan 1 0\n4 0 0 1\n")),
                     {"nan.msh:8:", "node 3", "non-finite"});
  expect_input_error(dir.write("inf.msh", tet_msh("1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 -inf\n")),
                     {"inf.msh:9:", "node 4", "non-finite"});
}

TEST(ReadMeshErrors, AbsurdCountsAreRefusedBeforeAllocating) {
  TempDir dir;
  expect_input_error(dir.write("huge.msh", tet_msh("1 0 0 0\n", "1 15 0 1\n", "1000000000000000")),
                     {"huge.msh:5:", "1000000000000000"});
  expect_input_error(dir.write("large.msh", tet_msh("1 0 0 0\n", "1 15 0 1\n", "100000000")),
                     {"large.msh:5:", "declares 100000000 nodes", "bytes are left"});
  expect_input_error(dir.write("negative.msh", tet_msh("1 0 0 0\n", "1 15 0 1\n", "-3")),
                     {"negative.msh:5:", "negative"});
  std::string elements = tet_msh();
  elements.replace(elements.find("$Elements\n1\n"), 12, "$Elements\n2000000000\n");
  expect_input_error(dir.write("elements.msh", elements), {"elements.msh:12:", "2000000000 elements"});
}

TEST(ReadMeshErrors, UnsupportedElementType) {
  TempDir dir;
  const std::string nodes = "1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
  // A type Gmsh has and the registry lacks (no element file gives Gmsh type 14).
  expect_input_error(dir.write("pyramid14.msh", tet_msh(nodes, "1 14 2 1 1 1 2 3 4 1 2 3 4 1 2 3 4 1 2\n")),
                     {"pyramid14.msh:13:", "type 14", "14-node pyramid", "not supported"});
  expect_input_error(dir.write("unknown.msh", tet_msh(nodes, "1 999 2 1 1 1 2 3 4\n")),
                     {"unknown.msh:13:", "unknown Gmsh element type 999"});
}

TEST(ReadMeshErrors, DuplicateNodeIds) {
  TempDir dir;
  expect_input_error(dir.write("dup.msh", tet_msh("1 0 0 0\n2 1 0 0\n2 0 1 0\n4 0 0 1\n")),
                     {"dup.msh:8:", "duplicate node id 2", "dup.msh:7)"});
}

TEST(ReadMeshErrors, UnquotedPhysicalName) {
  TempDir dir;
  std::string text = tet_msh();
  text.insert(text.find("$Nodes"), "$PhysicalNames\n1\n3 1 body\n$EndPhysicalNames\n");
  expect_input_error(dir.write("name.msh", text), {"name.msh:6:", "quoted"});
}

TEST(ReadMeshErrors, NoVolumeOrSurfaceElements) {
  TempDir dir;
  expect_input_error(dir.write("lines.msh", tet_msh("1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n", "1 1 2 1 1 1 2\n")),
                     {"lines.msh", "no 2D or 3D elements"});
}

TEST(ReadMeshErrors, FlatMeshOutsideThePlaneZ0) {
  TempDir dir;
  expect_input_error(dir.write("tilted.msh", tet_msh("1 0 0 0\n2 1 0 0\n3 0 1 0.5\n4 0 0 1\n", "1 2 2 1 1 1 2 3\n")),
                     {"tilted.msh", "node 3", "z = 0"});
}

TEST(ReadMeshErrors, MissingSection) {
  TempDir dir;
  const std::string text = tet_msh();
  expect_input_error(dir.write("noelements.msh", text.substr(0, text.find("$Elements"))),
                     {"noelements.msh", "no $Elements"});
}

TEST(ReadMeshErrors, TruncatedBinaryFile) {
  TempDir dir;
  const std::string text = test_support::read_file(meshtest::data_file("box_tet_o1.msh41b.msh"));
  const std::size_t nodes = text.find("$Nodes");
  expect_input_error(dir.write("cut41b.msh", text.substr(0, nodes + 200)), {"cut41b.msh: byte ", "truncated"});
  const std::string text22 = test_support::read_file(meshtest::data_file("box_tet_o1.msh22b.msh"));
  expect_input_error(dir.write("cut22b.msh", text22.substr(0, text22.find("$Elements") + 40)),
                     {"cut22b.msh: byte ", "truncated"});
}

TEST(ReadMeshErrors, BadEndiannessMarker) {
  TempDir dir;
  std::string text = test_support::read_file(meshtest::data_file("box_hex_o1.msh41b.msh"));
  text[text.find("4.1 1 8\n") + 8] = 7;
  expect_input_error(dir.write("endian.msh", text), {"endian.msh: byte 20", "endianness"});
}

TEST(ReadMeshErrors, AbsurdBinaryBlockSize) {
  TempDir dir;
  std::string text = test_support::read_file(meshtest::data_file("box_hex_o1.msh41b.msh"));
  const std::size_t elements = text.find("$Elements\n") + 10;
  const std::uint64_t huge = 1ull << 40;
  std::memcpy(&text[elements + 8], &huge, 8);        // numElements
  std::memcpy(&text[elements + 32 + 12], &huge, 8);  // numElementsInBlock of the first block
  expect_input_error(dir.write("blocks.msh", text), {"blocks.msh: byte ", "1099511627776"});
}

// --- VTK XML ------------------------------------------------------------------

std::string tet_vtu(const std::string& points = "0 0 0 1 0 0 0 1 0 0 0 1", const std::string& connectivity = "0 1 2 3",
                    const std::string& types = "10", const std::string& root_extra = "") {
  return "<?xml version=\"1.0\"?>\n"  // line 1
         "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\"" +
         root_extra +
         ">\n"                                                                                 // 2
         "<UnstructuredGrid>\n<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n"              // 3, 4
         "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n"  // 5, 6
         + points +
         "\n</DataArray>\n</Points>\n<Cells>\n"  // 7..10
         "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">" +
         connectivity +
         "</DataArray>\n"                                                               // 11
         "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">4</DataArray>\n"  // 12
         "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">" +
         types +
         "</DataArray>\n"  // 13
         "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

TEST(BadVtu, ValidReferenceFileReads) {
  TempDir dir;
  EXPECT_EQ(tensormass::read_mesh(dir.write("ok.vtu", tet_vtu())).cell_count(), 1);
}

TEST(BadVtu, CompressedData) {
  TempDir dir;
  expect_input_error(dir.write("zlib.vtu", tet_vtu("0 0 0 1 0 0 0 1 0 0 0 1", "0 1 2 3", "10",
                                                   " compressor=\"vtkZLibDataCompressor\"")),
                     {"zlib.vtu:2:", "vtkZLibDataCompressor", "not supported"});
}

TEST(BadVtu, GarbledNumber) {
  TempDir dir;
  expect_input_error(dir.write("garbled.vtu", tet_vtu("0 0 0 1 0 0\n0 1 zero 0 0 1")), {"garbled.vtu:8:", "'zero'"});
}

TEST(BadVtu, NodeIndexOutOfRange) {
  TempDir dir;
  expect_input_error(dir.write("range.vtu", tet_vtu("0 0 0 1 0 0 0 1 0 0 0 1", "0 1 2 40")),
                     {"range.vtu:11:", "cell 0", "node 40"});
}

TEST(BadVtu, NonFiniteCoordinate) {
  TempDir dir;
  expect_input_error(dir.write("nan.vtu", tet_vtu("0 0 0 1 0 0 0 1 0 0 0 nan")),
                     {"nan.vtu:6:", "node 3", "non-finite"});
}

TEST(BadVtu, UnsupportedCellType) {
  TempDir dir;
  expect_input_error(dir.write("polygon.vtu", tet_vtu("0 0 0 1 0 0 0 1 0 0 0 1", "0 1 2 3", "7")),
                     {"polygon.vtu:11:", "cell 0", "VTK_POLYGON", "not supported"});
}

TEST(BadVtu, WrongValueCount) {
  TempDir dir;
  expect_input_error(dir.write("short.vtu", tet_vtu("0 0 0 1 0 0 0 1 0")), {"short.vtu:6:", "9 values, expected 12"});
}

TEST(BadVtu, TruncatedXml) {
  TempDir dir;
  const std::string text = tet_vtu();
  expect_input_error(dir.write("cut.vtu", text.substr(0, text.find("<Cells>"))),
                     {"cut.vtu:", "unexpected end of file"});
}

TEST(BadVtu, AbsurdCounts) {
  TempDir dir;
  std::string text = tet_vtu();
  text.replace(text.find("NumberOfPoints=\"4\""), 18, "NumberOfPoints=\"1000000000000000\"");
  expect_input_error(dir.write("huge.vtu", text), {"huge.vtu:4:", "1000000000000000"});
}

TEST(BadVtu, BadBase64AndTruncatedAppendedData) {
  TempDir dir;
  std::string text = tet_vtu("@@@@not base64");
  text.replace(text.find("format=\"ascii\""), 14, "format=\"binary\"");
  expect_input_error(dir.write("b64.vtu", text), {"b64.vtu:6:", "base64"});
  const std::string appended =
      "<VTKFile type=\"UnstructuredGrid\" header_type=\"UInt32\"><UnstructuredGrid><Piece NumberOfPoints=\"4\" "
      "NumberOfCells=\"1\">"
      "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/></Points>"
      "</Piece></UnstructuredGrid><AppendedData encoding=\"raw\">_\xff\xff\xff\x7f" +
      std::string(20, '\0') + "</AppendedData></VTKFile>";
  const std::size_t data = appended.find('_', appended.find("<AppendedData")) + 1;
  expect_input_error(dir.write("appended.vtu", appended),
                     {"appended.vtu: byte " + std::to_string(data), "declares 2147483647 bytes"});
}

// Found by fuzz/fuzz_vtu_reader (kept as tests/data/fuzz_regressions/): an
// appended UInt64 header of 2^64 - 1 bytes went through a double, which
// rounds to 2^64, out of size_t's range (undefined behaviour).
TEST(BadVtu, FuzzRegressionAppendedHeaderOfUint64Max) {
  expect_input_error(test_support::source_path("tests/data/fuzz_regressions/vtu_reader/appended_header_uint64_max.vtu"),
                     {"appended_header_uint64_max.vtu: byte ", "declares 18446744073709551615 bytes",
                      "more than the whole file holds (257)"});
}

TEST(BadVtu, OtherDatasetType) {
  TempDir dir;
  expect_input_error(dir.write("poly.vtu", "<VTKFile type=\"PolyData\"><PolyData/></VTKFile>"),
                     {"poly.vtu:1:", "PolyData"});
}

// --- legacy VTK -----------------------------------------------------------------

std::string tet_vtk(const std::string& cells = "4 0 1 2 3", const std::string& type = "10",
                    const std::string& points = "0 0 0\n1 0 0\n0 1 0\n0 0 1") {
  return "# vtk DataFile Version 4.2\ntest\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n" + points +
         "\nCELLS 1 5\n" + cells + "\nCELL_TYPES 1\n" + type + "\n";
}

TEST(BadLegacyVtk, ValidReferenceFileReads) {
  TempDir dir;
  EXPECT_EQ(tensormass::read_mesh(dir.write("ok.vtk", tet_vtk())).cell_count(), 1);
}

TEST(BadLegacyVtk, NotAVtkFile) {
  TempDir dir;
  expect_input_error(dir.write("text.vtk", "solid cube\n"), {"text.vtk:1:", "not a legacy VTK file"});
}

TEST(BadLegacyVtk, OtherDataset) {
  TempDir dir;
  expect_input_error(dir.write("poly.vtk", "# vtk DataFile Version 4.2\nx\nASCII\nDATASET POLYDATA\n"),
                     {"poly.vtk:4:", "POLYDATA"});
}

TEST(BadLegacyVtk, NodeIndexOutOfRange) {
  TempDir dir;
  expect_input_error(dir.write("range.vtk", tet_vtk("4 0 1 2 17")), {"range.vtk:11:", "cell 0", "node 17"});
}

TEST(BadLegacyVtk, UnsupportedCellType) {
  TempDir dir;
  expect_input_error(dir.write("voxel.vtk", tet_vtk("4 0 1 2 3", "11")),
                     {"voxel.vtk:11:", "VTK_VOXEL", "not supported"});
}

TEST(BadLegacyVtk, WrongNodeCountForTheType) {
  TempDir dir;
  expect_input_error(dir.write("count.vtk", tet_vtk("4 0 1 2 3", "12")), {"count.vtk:11:", "has 4 nodes, expected 8"});
}

TEST(BadLegacyVtk, GarbledNumberAndTruncation) {
  TempDir dir;
  expect_input_error(dir.write("garbled.vtk", tet_vtk("4 0 1 2 3", "10", "0 0 0\n1 0 0\n0 one 0\n0 0 1")),
                     {"garbled.vtk:8:", "'one'"});
  const std::string text = tet_vtk();
  expect_input_error(dir.write("cut.vtk", text.substr(0, text.find("CELLS") + 14)), {"cut.vtk:", "truncated"});
}

TEST(BadLegacyVtk, AbsurdCount) {
  TempDir dir;
  std::string text = tet_vtk();
  text.replace(text.find("POINTS 4"), 8, "POINTS 99999999999");
  expect_input_error(dir.write("huge.vtk", text), {"huge.vtk:5:", "99999999999"});
}

TEST(BadLegacyVtk, TruncatedBinary) {
  TempDir dir;
  const std::string text = test_support::read_file(meshtest::data_file("hybrid_o1.v42b.vtk"));
  expect_input_error(dir.write("cut.vtk", text.substr(0, text.find("CELL_TYPES") - 100)),
                     {"cut.vtk: byte ", "truncated"});
}

// --- Robustness: every committed mesh, truncated and corrupted -----------------

void read_or_refuse(const std::string& path) {
  try {
    tensormass::read_mesh(path);
  } catch (const tensormass::InputError& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
  } catch (const std::exception& error) {
    ADD_FAILURE() << path << ": " << error.what();
  }
}

std::vector<std::string> committed_meshes() {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(meshtest::data_dir())) {
    const std::string extension = entry.path().extension().string();
    if (extension == ".msh" || extension == ".vtu" || extension == ".vtk")
      files.push_back(entry.path().filename().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(ReadMeshRobustness, TruncatedCopiesAreRefusedCleanly) {
  TempDir dir;
  for (const std::string& name : committed_meshes()) {
    const std::string text = test_support::read_file(meshtest::data_file(name));
    for (int k = 1; k < 24; ++k) {
      SCOPED_TRACE(name + " cut " + std::to_string(k));
      read_or_refuse(dir.write("cut_" + name, text.substr(0, text.size() * static_cast<std::size_t>(k) / 24)));
    }
  }
}

TEST(ReadMeshRobustness, CorruptedCopiesAreReadOrRefusedCleanly) {
  TempDir dir;
  std::mt19937 random(12345);
  for (const std::string& name : committed_meshes()) {
    const std::string text = test_support::read_file(meshtest::data_file(name));
    for (int trial = 0; trial < 40; ++trial) {
      std::string copy = text;
      for (int k = 0; k < 1 + trial % 4; ++k) {
        const std::size_t at = std::uniform_int_distribution<std::size_t>(0, copy.size() - 1)(random);
        copy[at] = static_cast<char>(std::uniform_int_distribution<int>(0, 255)(random));
      }
      SCOPED_TRACE(name + " trial " + std::to_string(trial));
      read_or_refuse(dir.write("bad_" + name, copy));
    }
  }
}

// Only regular files are read: a FIFO would block the open, a device
// (/dev/zero through a link) never ends, a socket cannot be read.
TEST(ReadMeshErrors, FifoIsRefusedWithoutBlocking) {
  TempDir dir;
  ASSERT_EQ(::mkfifo(dir.file("pipe.msh").c_str(), 0600), 0);
  expect_input_error(dir.file("pipe.msh"), {"pipe.msh", "FIFO", "regular file"});
}

TEST(ReadMeshErrors, DeviceThroughALinkIsRefused) {
  TempDir dir;
  std::filesystem::create_symlink("/dev/zero", dir.file("zero.vtk"));
  expect_input_error(dir.file("zero.vtk"), {"zero.vtk", "character device", "regular file"});
}

TEST(ReadMeshErrors, SocketIsRefused) {
  TempDir dir;
  const std::string path = dir.file("socket.vtu");
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  ASSERT_LT(path.size(), sizeof(address.sun_path));
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)), 0);
  expect_input_error(path, {"socket.vtu", "socket", "regular file"});
  ::close(fd);
}

}  // namespace
