// Bad surface files: each refused with InputError naming the file and the
// line (or byte) and what is wrong.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>

#include "support/test_surfaces.hpp"
#include "tensormass/surface/surface.hpp"

namespace {

using namespace surfacetest;
using test_support::TempDir;

TEST(SurfaceBadInput, MissingFile) {
  TempDir dir;
  expect_read_error(dir.file("nowhere.stl"), {"nowhere.stl", "cannot open"});
  expect_read_error(dir.file("nowhere.msh"), {"nowhere.msh", "cannot open"});
}

TEST(SurfaceBadInput, UnknownExtensionAndEmptyFile) {
  TempDir dir;
  expect_read_error(dir.write("surface.ply", "ply\n"), {"surface.ply", "'.ply'"});
  expect_read_error(dir.write("empty.stl", ""), {"empty.stl", "empty"});
  expect_read_error(dir.write("blank.obj", "\n \n"), {"blank.obj", "empty"});
}

TEST(SurfaceBadInput, TruncatedBinaryStl) {
  TempDir dir;
  std::string data = binary_stl(unit_tetrahedron(), "binary");
  data.resize(data.size() - 10);
  expect_read_error(dir.write("cut.stl", data), {"cut.stl", "truncated", "4 triangles", "284 bytes", "274"});
  // A header starting with "solid" does not make a binary file ASCII.
  data = binary_stl(unit_tetrahedron(), "solid tet");
  data.resize(data.size() - 60);
  expect_read_error(dir.write("cut_solid.stl", data), {"cut_solid.stl", "truncated"});
  expect_read_error(dir.write("short.stl", std::string(40, '\0')), {"short.stl", "too short"});
}

TEST(SurfaceBadInput, BinaryStlTrailingBytesAndNaN) {
  TempDir dir;
  std::string data = binary_stl(unit_tetrahedron(), "binary") + "extra";
  expect_read_error(dir.write("long.stl", data), {"long.stl", "5 more bytes"});
  TriangleSurface bad = unit_tetrahedron();
  bad.points[4] = std::nan("");
  expect_read_error(dir.write("nan.stl", binary_stl(bad, "binary")), {"nan.stl", "byte ", "not a finite"});
}

TEST(SurfaceBadInput, AsciiStlBadNumberNamesTheLine) {
  TempDir dir;
  const std::string text =
      "solid a\n"
      "facet normal 0 0 1\n"
      " outer loop\n"
      "  vertex 0 0 0\n"
      "  vertex 1 0 1.5x\n"
      "  vertex 0 1 0\n"
      " endloop\n"
      "endfacet\n"
      "endsolid a\n";
  expect_read_error(dir.write("bad.stl", text), {"bad.stl:5:", "'1.5x'"});
  std::string nan_text = text;
  nan_text.replace(nan_text.find("1.5x"), 4, "nan");
  expect_read_error(dir.write("nan.stl", nan_text), {"nan.stl:5:", "not a finite"});
  std::string short_text = text;
  short_text.replace(short_text.find(" 1.5x"), 5, "");
  expect_read_error(dir.write("short.stl", short_text), {"short.stl:5:", "vertex X Y Z"});
}

TEST(SurfaceBadInput, AsciiStlStructure) {
  TempDir dir;
  const std::string facet =
      "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\n";
  expect_read_error(dir.write("open.stl", "solid a\n" + facet), {"open.stl:", "solid 'a'", "endsolid"});
  expect_read_error(dir.write("cut.stl", "solid a\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n"),
                    {"cut.stl:4:", "facet started at line 2", "truncated"});
  expect_read_error(dir.write("word.stl", "solid a\n" + facet + "bogus\nendsolid a\n"), {"word.stl:9:", "'bogus'"});
  expect_read_error(dir.write("two.stl",
                              "solid a\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n"
                              " endloop\nendfacet\nendsolid a\n"),
                    {"two.stl:6:", "2 vertices"});
  expect_read_error(dir.write("none.stl", "solid empty\nendsolid empty\n"), {"none.stl", "no triangles"});
}

TEST(SurfaceBadInput, ObjErrors) {
  TempDir dir;
  expect_read_error(dir.write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n"),
                    {"range.obj:5:", "vertex index 4", "out of range", "3 vertices"});
  expect_read_error(dir.write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), {"zero.obj:4:", "index 0"});
  expect_read_error(dir.write("negative.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n"), {"negative.obj:3:", "-3"});
  expect_read_error(dir.write("number.obj", "v 0 0 0\nv 1 zero 0\n"), {"number.obj:2:", "'zero'"});
  expect_read_error(dir.write("inf.obj", "v 0 0 0\nv 1 inf 0\n"), {"inf.obj:2:", "not a finite"});
  expect_read_error(dir.write("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n"), {"two.obj:3:", "at least 3"});
  expect_read_error(dir.write("corner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x/1\n"), {"corner.obj:4:", "'x/1'"});
  expect_read_error(dir.write("points.obj", "v 0 0 0\nv 1 0 0\n"), {"points.obj", "no triangles"});
}

// Found by fuzz/fuzz_obj_reader (kept as tests/data/fuzz_regressions/): the
// relative index -9223372036854775808 was negated to check its range, a
// signed overflow (undefined behaviour).
TEST(SurfaceBadInput, FuzzRegressionFaceIndexLongMin) {
  expect_read_error(test_support::source_path("tests/data/fuzz_regressions/obj_reader/face_index_long_min.obj"),
                    {"face_index_long_min.obj:1:", "relative vertex index -9223372036854775808",
                     "before the first vertex (0 defined so far)"});
}

TEST(SurfaceBadInput, GmshErrors) {
  TempDir dir;
  expect_read_error(dir.write("bad.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 x\n"),
                    {"bad.msh", "Gmsh"});
  expect_read_error(dir.write("lines.msh",
                              "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 1 0 0\n$EndNodes\n"
                              "$Elements\n1\n1 1 2 0 1 1 2\n$EndElements\n"),
                    {"lines.msh", "no triangles"});
  expect_read_error(dir.write("quads.msh",
                              "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n"
                              "$EndNodes\n$Elements\n1\n7 3 2 0 1 1 2 3 4\n$EndElements\n"),
                    {"quads.msh", "element 7", "type 3"});
}

TEST(SurfaceBadInput, OnlyRegularFilesAreRead) {
  TempDir dir;
  ASSERT_EQ(::mkfifo(dir.file("pipe.stl").c_str(), 0600), 0);
  expect_read_error(dir.file("pipe.stl"), {"pipe.stl", "FIFO", "regular file"});
  std::filesystem::create_symlink("/dev/zero", dir.file("zero.obj"));
  expect_read_error(dir.file("zero.obj"), {"zero.obj", "character device"});
  std::filesystem::create_directory(dir.file("folder.msh"));
  expect_read_error(dir.file("folder.msh"), {"folder.msh", "directory"});
}

}  // namespace
