// tests/scripts/check_test_mirror.py under /usr/bin/python3: the source tree
// passes; in a tree made here a source without its test file, an allowed
// source that has one now and an allowed one that is gone are each named.
#include <gtest/gtest.h>

#include <string>

#include "support/test_support.hpp"

namespace {

using test_support::Result;
using test_support::TempDir;

Result check_mirror(const std::string& root) {
  return test_support::python(test_support::source_path("tests/scripts/check_test_mirror.py") + " --root '" + root +
                              "'");
}

TEST(CheckTestMirror, TheSourceTreeIsMirrored) {
  const Result result = check_mirror(test_support::source_path(""));
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("test mirror: "), std::string::npos) << result.output;
}

TEST(CheckTestMirror, ASourceWithoutItsTestFileIsNamed) {
  const TempDir dir;
  dir.write("runtime/src/mesh/mesh.cpp", "\n");
  dir.write("tests/runtime/mesh/test_mesh_arrays.cpp", "\n");  // test_mesh*.cpp: mesh.cpp is mirrored
  dir.write("runtime/src/mesh/mesh_cut.cpp", "\n");
  dir.write("runtime/src/kernels/registry.cpp", "\n");
  dir.write("tests/kernels/test_registry.cpp", "\n");
  const Result result = check_mirror(dir.path().string());
  EXPECT_EQ(result.exit_code, 1) << result.output;
  test_support::expect_contains(result.output,
                                {"runtime/src/mesh/mesh_cut.cpp: no tests/runtime/mesh/test_mesh_cut*.cpp"});
  EXPECT_EQ(result.output.find("runtime/src/mesh/mesh.cpp:"), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("registry.cpp"), std::string::npos) << result.output;
}

TEST(CheckTestMirror, AllowedEntriesMustStillNeedTheirPlace) {
  const TempDir dir;
  dir.write("runtime/src/simulation/state_frames.cpp", "\n");  // an allowed source that has its test file now
  dir.write("tests/runtime/simulation/test_state_frames.cpp", "\n");
  const Result result = check_mirror(dir.path().string());
  EXPECT_EQ(result.exit_code, 1) << result.output;
  test_support::expect_contains(
      result.output,
      {"runtime/src/simulation/state_frames.cpp: has tests/runtime/simulation/test_state_frames.cpp now; remove it "
       "from ALLOWED",
       "runtime/src/simulation/carry_laws.cpp: listed in ALLOWED but there is no such source"});
}

TEST(CheckTestMirror, ATreeWithoutRuntimeSourcesIsRefused) {
  const TempDir dir;
  const Result result = check_mirror(dir.path().string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("runtime/src"), std::string::npos) << result.output;
}

}  // namespace
