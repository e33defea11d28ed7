// `tensormass mesh-info`: run as a process (TENSORMASS_BINARY): text and
// JSON reports agree with what Gmsh says about the test meshes, inverted
// elements are listed with a warning (exit 0), bad input exits 2 with one
// line on stderr naming the file.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <string>

#include "support/test_meshes.hpp"

namespace {

using test_support::Result;

/// Runs `tensormass mesh-info ARGUMENTS`, stdout (output) and stderr (error) apart.
Result mesh_info(const std::string& arguments) {
  return test_support::shell_apart("'" TENSORMASS_BINARY "' mesh-info " + arguments);
}

std::string quoted(const std::string& path) { return "'" + path + "'"; }

int line_count(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

TEST(MeshInfo, TextReport) {
  const Result run = mesh_info(quoted(meshtest::data_file("hybrid_o1.msh41.msh")));
  ASSERT_EQ(run.exit_code, 0) << run.error;
  EXPECT_EQ(run.error, "");
  for (const char* piece :
       {"dimension       3", "nodes           57", "cells           125", "hex8", "prism6", "pyramid5", "tet4", "lower",
        "upper", "bottom", "top", "min_sj", "max edge ratio", "volume          1\n", "inverted        0"})
    EXPECT_NE(run.output.find(piece), std::string::npos) << "missing '" << piece << "' in\n" << run.output;
}

TEST(MeshInfo, JsonReportMatchesGmsh) {
  for (const std::string stem : {"box_tet_o2", "plate2d_o1", "hybrid_o1"}) {
    const Result run = mesh_info(quoted(meshtest::data_file(stem + ".msh22b.msh")) + " --json");
    ASSERT_EQ(run.exit_code, 0) << run.error;
    const nlohmann::json report = nlohmann::json::parse(run.output);
    const nlohmann::json& expected = meshtest::expected_meshes()[stem];
    EXPECT_EQ(report["dimension"].get<int>(), expected["dim"].get<int>());
    EXPECT_EQ(report["nodes"].get<int>(), expected["nodes"].get<int>());
    for (const auto& [type, count] : expected["cells"].items()) {
      EXPECT_EQ(report["element_types"][type].get<int>(), count.get<int>()) << stem << " " << type;
      EXPECT_EQ(report["quality"][type]["count"].get<int>(), count.get<int>());
      EXPECT_GT(report["quality"][type]["min_scaled_jacobian"].get<double>(), 0);
      EXPECT_LE(report["quality"][type]["max_scaled_jacobian"].get<double>(), 1 + 1e-12);
      EXPECT_GE(report["quality"][type]["max_edge_ratio"].get<double>(), 1);
    }
    ASSERT_EQ(report["groups"].size(), expected["groups"].size());
    for (const nlohmann::json& group : report["groups"]) {
      const nlohmann::json& want = expected["groups"][group["name"].get<std::string>()];
      EXPECT_EQ(group["dim"].get<int>(), want["dim"].get<int>()) << group["name"].get<std::string>();
      EXPECT_EQ(group["nodes"].get<int>(), want["nodes"].get<int>());
      EXPECT_EQ(group["cells"].get<int>(), want["cells"].get<int>());
      EXPECT_EQ(group["facets"].get<int>(), want["facets"].get<int>());
    }
    EXPECT_NEAR(report["volume"].get<double>(), expected["volume"].get<double>(), 1e-12);
    EXPECT_TRUE(report["inverted"].empty());
  }
}

TEST(MeshInfo, InvertedElementsAreListedWithAWarning) {
  test_support::TempDir dir;
  // Two tetrahedra; element 20 has two nodes swapped (negative volume).
  const std::string path =
      dir.write("flipped.msh",
                "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                "$Nodes\n1 5 1 5\n3 1 0 5\n1\n2\n3\n4\n5\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n$EndNodes\n"
                "$Elements\n1 2 10 20\n3 1 4 2\n10 1 2 3 4\n20 3 2 4 5\n$EndElements\n");
  const Result text = mesh_info(quoted(path));
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.output.find("inverted        1"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("element 1 (tet4, id 20 in " + path + ")"), std::string::npos) << text.output;
  EXPECT_EQ(line_count(text.error), 1) << text.error;
  EXPECT_NE(text.error.find("warning: 1 inverted element"), std::string::npos) << text.error;

  const Result json = mesh_info(quoted(path) + " --json");
  EXPECT_EQ(json.exit_code, 0);
  const nlohmann::json report = nlohmann::json::parse(json.output);
  ASSERT_EQ(report["inverted"].size(), 1u);
  EXPECT_EQ(report["inverted"][0]["cell"].get<int>(), 1);
  EXPECT_EQ(report["inverted"][0]["source_id"].get<int>(), 20);
  EXPECT_EQ(report["inverted"][0]["element"].get<std::string>(), "tet4");
  EXPECT_EQ(report["quality"]["tet4"]["inverted"].get<int>(), 1);
  EXPECT_LT(report["quality"]["tet4"]["min_scaled_jacobian"].get<double>(), 0);
}

TEST(MeshInfo, BadInputExitsTwoWithOneLine) {
  test_support::TempDir dir;
  const std::string garbled = dir.write("garbled.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\nfour\n");
  const Result bad = mesh_info(quoted(garbled));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(bad.output, "");
  EXPECT_EQ(line_count(bad.error), 1) << bad.error;
  EXPECT_NE(bad.error.find("garbled.msh:5:"), std::string::npos) << bad.error;

  const Result missing = mesh_info(quoted(dir.file("absent.vtu")));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_EQ(line_count(missing.error), 1) << missing.error;
  EXPECT_NE(missing.error.find("absent.vtu"), std::string::npos);
}

// The extreme node ids of a hostile file are read (they crashed the index),
// a FIFO is refused at once (it blocked the open): exit 0 and 2, never a signal or a hang.
TEST(MeshInfo, HostileFilesEndWithAnExitCode) {
  test_support::TempDir dir;
  const std::string extreme = dir.write("extreme.msh",
                                        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n-9223372036854775808 0 0 0\n"
                                        "9223372036854775807 1 0 0\n2 0 1 0\n3 0 0 1\n$EndNodes\n$Elements\n1\n"
                                        "1 4 2 1 1 -9223372036854775808 9223372036854775807 2 3\n$EndElements\n");
  const Result read = mesh_info(quoted(extreme));
  EXPECT_EQ(read.exit_code, 0) << read.error;
  EXPECT_NE(read.output.find("cells           1"), std::string::npos) << read.output;

  ASSERT_EQ(::mkfifo(dir.file("pipe.msh").c_str(), 0600), 0);
  const Result fifo =
      test_support::shell_apart("timeout 20 '" TENSORMASS_BINARY "' mesh-info " + quoted(dir.file("pipe.msh")));
  EXPECT_EQ(fifo.exit_code, 2);
  EXPECT_EQ(line_count(fifo.error), 1) << fifo.error;
  EXPECT_NE(fifo.error.find("pipe.msh: is a FIFO"), std::string::npos) << fifo.error;
}

TEST(MeshInfo, UsageErrors) {
  EXPECT_EQ(mesh_info("").exit_code, 2);
  EXPECT_EQ(mesh_info("--frobnicate x.msh").exit_code, 2);
  EXPECT_EQ(mesh_info("a.msh b.msh").exit_code, 2);
  const Result help = mesh_info("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("usage: tensormass mesh-info FILE [--json]"), std::string::npos);
}

}  // namespace
