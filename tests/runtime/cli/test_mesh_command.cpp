// `tensormass mesh` through the binary: the written mesh reads back with its
// groups; bad input exits 2 and writes nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/test_support.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/mesh/mesh.hpp"
#include "tensormass/mesh/mesh_quality.hpp"

namespace {

namespace fs = std::filesystem;
using test_support::Result;

Result run(const std::string& arguments) { return test_support::tensormass(arguments); }

std::string surface(const std::string& name) {
  return std::string(TENSORMASS_SOURCE_DIR) + "/tests/data/surfaces/" + name + ".stl";
}

class MeshCommand : public ::testing::Test {
 protected:
  std::string out() const { return dir_.file("out.msh"); }
  void expect_input_error(const std::string& arguments, const std::string& message) {
    const Result result = run("mesh " + arguments + " -o " + out());
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_NE(result.output.find(message), std::string::npos) << result.output;
    EXPECT_FALSE(fs::exists(out()));
  }
  test_support::TempDir dir_;
};

TEST_F(MeshCommand, WritesAMeshWithGroupsAndReportsQuality) {
  const Result result = run("mesh " + surface("cut_ball") +
                            " --size 0.3 --roi 0,0,0,0.3,0.1 --region inner=" + surface("sphere") + " -o " + out());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const char* expected : {"hex8", "pyramid5", "tet4", "min SJ", "relative difference", "conformity"})
    EXPECT_NE(result.output.find(expected), std::string::npos) << expected << "\n" << result.output;
  const tensormass::Mesh mesh = tensormass::read_mesh(out());
  for (const char* group : {"body", "surface", "flat", "round", "inner"})
    EXPECT_NE(mesh.group(group), nullptr) << group;
  // Every cell's centroid is inside the unit sphere: all cells are in "inner".
  EXPECT_EQ(mesh.group("inner")->cells.size(), static_cast<std::size_t>(mesh.cell_count()));
  EXPECT_TRUE(tensormass::mesh_quality(mesh).inverted_cells.empty());
}

TEST_F(MeshCommand, BadOptionsExitTwoAndWriteNothing) {
  expect_input_error(surface("sphere"), "missing --size");
  expect_input_error(surface("sphere") + " --size abc", "not a number");
  expect_input_error(surface("sphere") + " --size 0.2 --levels 1.5", "--levels");
  expect_input_error(surface("sphere") + " --size 0.2 --roi 1,2,3", "--roi");
  expect_input_error(surface("sphere") + " --size 0.2 --region noequals", "NAME=FILE");
  expect_input_error(surface("sphere") + " --size 0.2 --frobnicate 1", "unknown option");
  expect_input_error(dir_.file("missing.stl") + " --size 0.2", "missing.stl");
}

TEST_F(MeshCommand, OpenSurfaceIsRefused) {
  const fs::path open = dir_.path() / "open.stl";
  // A tetrahedron with one face missing.
  std::ofstream(open) << "solid open\n"
                         "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
                         "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
                         "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
                         "endsolid open\n";
  expect_input_error(open.string() + " --size 0.2", "open.stl");
}

}  // namespace
