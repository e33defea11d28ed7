// `tensormass beam`: exit codes, messages, summary and the written file.
#include <gtest/gtest.h>

#include "support/python_check.hpp"
#include "tensormass/meshing/beam.hpp"

namespace {

using test_support::Result;
using test_support::TempDir;

/// Runs `tensormass beam ARGS` in `dir`, capturing stdout (output) and stderr (error) apart.
Result beam_cli(const TempDir& dir, const std::string& args) {
  return test_support::shell_apart("cd '" + dir.path().string() + "' && '" TENSORMASS_BINARY "' beam " + args);
}

TEST(BeamCli, DefaultIsTheOrigin600QuadBeam) {
  const TempDir dir;
  const Result result = beam_cli(dir, "-o beam.msh");
  EXPECT_EQ(result.exit_code, 0) << result.error;
  EXPECT_NE(result.output.find("671 nodes, 600 cells (600 quad4)"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("clamp"), std::string::npos);
  EXPECT_EQ(dir.files(), std::vector<std::string>{"beam.msh"});
}

TEST(BeamCli, HelpExitsZero) {
  const TempDir dir;
  const Result result = beam_cli(dir, "--help");
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_NE(result.output.find("--mix TYPE:F"), std::string::npos);
  EXPECT_TRUE(dir.files().empty());
}

TEST(BeamCli, MixedThreeDimensionalBeamReadsBackInGmsh) {
  const TempDir dir;
  const Result result =
      beam_cli(dir, "--dim 3 --cells 6,2,2 --size 3,0.5,0.5 --mix hex8:0.5,tet5:0.5 --format 2.2 -o beam.msh");
  ASSERT_EQ(result.exit_code, 0) << result.error;
  EXPECT_NE(result.output.find("phase_tet5"), std::string::npos) << result.output;
  tensormass::BeamSpec spec;
  spec.dim = 3;
  spec.cells = {6, 2, 2};
  spec.size = {3, 0.5, 0.5};
  spec.phases = tensormass::parse_beam_mix("hex8:0.5,tet5:0.5");
  dir.write("expected.json", tmtest::msh_expectation(tensormass::make_beam(spec)));
  EXPECT_EQ(tmtest::run_check("check_msh.py", dir.file("beam.msh"), dir.file("expected.json")), 0);
  EXPECT_EQ(test_support::read_file(dir.file("beam.msh")).rfind("$MeshFormat\n2.2", 0), 0u);
}

TEST(BeamCli, OptionsWithEqualsAndOrder2) {
  const TempDir dir;
  const Result result = beam_cli(dir, "--dim=2 --cells=4,2 --type=tri3 --order=2 --output=b.msh");
  EXPECT_EQ(result.exit_code, 0) << result.error;
  EXPECT_NE(result.output.find("16 tri6"), std::string::npos) << result.output;
}

TEST(BeamCli, BadArgumentsExitTwoWithAMessageAndWriteNothing) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"--type hex9 -o b.msh", "unknown cell type 'hex9'"},
      {"--mix tri3:0.3,quad4:0.6 -o b.msh", "sum to"},
      {"--cells 0,10 -o b.msh", "at least 1"},
      {"--type tet5 -o b.msh", "'tet5' is a 3D cell type"},
      {"--dim 3 --cells 4,2,2 --mix hex27:0.5,tet5:0.5 -o b.msh", "face-centre nodes"},
      {"--dim 3 --cells 4,2 -o b.msh", "needs 3 counts"},
      {"--cells 4,x -o b.msh", "not a number"},
      {"--format 3.0 -o b.msh", "expected 4.1 or 2.2"},
      {"--dim 4 -o b.msh", "expected 2 or 3"},
      {"--type quad4 --mix tri3:1 -o b.msh", "one of --type or --mix"},
      {"--bogus 1 -o b.msh", "unknown option '--bogus'"},
      {"--type", "needs a value"},
      {"--type tri3", "missing -o"},
      {"b.msh", "unexpected argument 'b.msh'"},
      {"-o missing/b.msh", "missing/b.msh"},
  };
  for (const auto& [args, phrase] : cases) {
    const TempDir dir;
    const Result result = beam_cli(dir, args);
    EXPECT_EQ(result.exit_code, 2) << args;
    EXPECT_NE(result.error.find(phrase), std::string::npos) << args << ": " << result.error;
    EXPECT_TRUE(dir.files().empty()) << args;
  }
}

}  // namespace
