// Choosing the mesh reader (tensormass/io/read_mesh.hpp): by the extension in
// any case, never by the content, an unknown extension refused before the
// file is opened, and the in-memory entry point reading the same bytes as the
// file. (Each reader's errors: test_read_mesh_errors.cpp; what each format
// holds: test_gmsh_reader.cpp, test_vtu_reader.cpp, test_vtk_legacy_reader.cpp.)
#include <gtest/gtest.h>

#include <string>

#include "io/mesh_readers.hpp"
#include "support/test_meshes.hpp"
#include "tensormass/io/read_mesh.hpp"

namespace {

using test_support::TempDir;

/// The message of the InputError read_mesh throws for `path` ("" when it throws none).
std::string read_error(const std::string& path) {
  try {
    tensormass::read_mesh(path);
  } catch (const tensormass::InputError& error) {
    return error.what();
  }
  return "";
}

const char* kTetMsh =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
    "$Elements\n1\n1 4 2 1 1 1 2 3 4\n$EndElements\n";

TEST(ReadMesh, TheExtensionChoosesTheReaderInAnyCase) {
  const TempDir dir;
  for (const char* name : {"tet.msh", "tet.MSH", "tet.Msh"}) {
    const tensormass::Mesh mesh = tensormass::read_mesh(dir.write(name, kTetMsh));
    EXPECT_EQ(mesh.cell_count(), 1) << name;
    EXPECT_EQ(mesh.source, dir.file(name));
  }
  const std::string vtu = test_support::read_file(meshtest::data_file("box_tet_o2.ascii.vtu"));
  EXPECT_EQ(tensormass::read_mesh(dir.write("box.VTU", vtu)).cell_count(),
            tensormass::read_mesh(meshtest::data_file("box_tet_o2.ascii.vtu")).cell_count());
}

TEST(ReadMesh, TheContentDoesNotChooseTheReader) {
  const TempDir dir;
  const std::string message = read_error(dir.write("tet.vtk", kTetMsh));
  EXPECT_EQ(message.rfind(dir.file("tet.vtk") + ":1: ", 0), 0u) << message;
  EXPECT_NE(message.find("not a legacy VTK file"), std::string::npos) << message;
}

TEST(ReadMesh, AnUnknownExtensionIsRefusedBeforeTheFileIsOpened) {
  const TempDir dir;
  // The file does not exist: the extension is what is refused.
  EXPECT_EQ(read_error(dir.file("liver.stl")),
            dir.file("liver.stl") + ": unknown mesh format '.stl' (expected .msh, .vtu or .vtk)");
  EXPECT_EQ(read_error(dir.file("mesh")), dir.file("mesh") + ": unknown mesh format '' (expected .msh, .vtu or .vtk)");
  EXPECT_EQ(read_error(dir.write("mesh.msh.gz", kTetMsh)),
            dir.file("mesh.msh.gz") + ": unknown mesh format '.gz' (expected .msh, .vtu or .vtk)");
}

TEST(ReadMesh, AFileOfWhitespaceIsEmpty) {
  const TempDir dir;
  EXPECT_EQ(read_error(dir.write("blank.msh", " \t\r\n\n")), dir.file("blank.msh") + ": the file is empty");
}

TEST(ReadMeshData, ReadsTheBytesAsTheFileWouldBeRead) {
  for (const char* name : {"box_hex_o1.msh41b.msh", "hybrid_o1.b64.vtu", "hybrid_o1.v42b.vtk"}) {
    const std::string path = meshtest::data_file(name);
    const tensormass::Mesh from_bytes = tensormass::detail::read_mesh_data(path, test_support::read_file(path));
    meshtest::expect_identical(from_bytes, tensormass::read_mesh(path), true);
  }
  EXPECT_THROW(tensormass::detail::read_mesh_data("bytes.obj", kTetMsh), tensormass::InputError);
  EXPECT_THROW(tensormass::detail::read_mesh_data("bytes.msh", "\n"), tensormass::InputError);
}

}  // namespace
