// The adaptive model end to end (run_scene on a 2D beam): limits of the
// threshold, accuracy in between, blending continuity, exact downgrade.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "support/cantilever.hpp"
#include "support/test_support.hpp"
#include "tensormass/adaptivity/adaptivity.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/io/gmsh_writer.hpp"
#include "tensormass/meshing/beam.hpp"
#include "tensormass/simulation/simulation.hpp"

namespace tensormass {
namespace {

namespace fs = std::filesystem;

class AdaptiveBeam : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<test_support::TempDir>();
    directory_ = dir_->path();
    BeamSpec spec;
    spec.cells = {30, 5, 1};
    spec.size = {6.0, 1.0, 1.0};
    io::write_msh((directory_ / "beam.msh").string(), make_beam(spec));
  }
  static void TearDownTestSuite() { dir_.reset(); }

  /// The origin's experiment: a soft cantilever sagging about a third of its length.
  static Scene scene(const std::string& law, const std::string& criterion = "", double threshold = 0) {
    Scene s = test::cantilever(law);
    s.path = (directory_ / "scene.yaml").string();
    s.mesh = (directory_ / "beam.msh").string();
    s.model.materials[0].young = 1e7;
    s.solver.load_steps = 4;
    s.output.directory = (directory_ / ("out-" + law + criterion + std::to_string(threshold))).string();
    if (!criterion.empty()) {
      s.adaptivity.enabled = true;
      s.adaptivity.criteria = {{criterion, threshold, 0}};
    }
    return s;
  }

  static RunReport run(const Scene& s) {
    RunOptions options;
    options.progress = false;
    return run_scene(s, options);
  }

  static double max_difference(const RunReport& a, const RunReport& b) {
    double worst = 0;
    for (std::size_t i = 0; i < a.state.displacement.size(); ++i)
      worst = std::max(worst, std::abs(a.state.displacement[i] - b.state.displacement[i]));
    return worst;
  }

  static inline std::unique_ptr<test_support::TempDir> dir_;  ///< shared by the suite's tests
  static inline fs::path directory_;
};

TEST_F(AdaptiveBeam, HugeThresholdIsExactlyPureHooke) {
  const RunReport hooke = run(scene("hooke"));
  const RunReport adaptive = run(scene("hooke", "R_NL", 1e9));
  EXPECT_EQ(adaptive.switches, 0);
  EXPECT_EQ(max_difference(hooke, adaptive), 0.0);
}

TEST_F(AdaptiveBeam, ZeroThresholdIsPureStvk) {
  const RunReport stvk = run(scene("stvk"));
  const RunReport adaptive = run(scene("hooke", "R_NL", 0.0));
  EXPECT_EQ(adaptive.switches, 150);
  EXPECT_LT(max_difference(stvk, adaptive), 1e-6 * stvk.max_displacement);
}

TEST_F(AdaptiveBeam, IntermediateThresholdUpgradesSomeAndBeatsHooke) {
  const RunReport stvk = run(scene("stvk"));
  const RunReport hooke = run(scene("hooke"));
  const RunReport adaptive = run(scene("hooke", "R_NL", 0.01));
  EXPECT_GT(adaptive.switches, 0);
  EXPECT_LT(adaptive.switches, 150);
  EXPECT_LT(max_difference(stvk, adaptive), 0.5 * max_difference(stvk, hooke));
  // The final state is in equilibrium for the final laws: the last
  // evaluation switched nothing.
  ASSERT_FALSE(adaptive.adaptivity.empty());
  EXPECT_EQ(adaptive.adaptivity.back().upgrades, 0);
}

TEST_F(AdaptiveBeam, EveryCriterionRunsAndWritesItsField) {
  for (const std::string& name : criterion_names()) {
    Scene s = scene("hooke", name, name == "R_VL" || name == "R_VLX" ? 0.01 : 1e9);
    const RunReport report = run(s);
    EXPECT_EQ(report.switches, 0) << name;
    EXPECT_TRUE(fs::exists(fs::path(s.output.directory) / "final.vtu")) << name;
  }
}

TEST(Adaptivity, BlendingStartsWithoutAJumpAndReachesTheNewLaw) {
  BeamSpec spec;
  spec.cells = {6, 2, 1};
  const Mesh mesh = make_beam(spec);
  Scene s;
  s.path = "blend.yaml";
  MaterialSpec material{"all", "hooke", "", 1e6, 0.3, 1000, 0};
  s.model.materials = {material};
  s.model.fixed = {"clamp"};
  Model model(mesh, s.model);
  const Assembler assembler(model);
  AdaptivitySettings adaptive;
  adaptive.enabled = true;
  adaptive.criteria = {{"R_NL", 0.0, 0}};
  adaptive.blend_steps = 4;
  Adaptivity adaptivity(adaptive, model, assembler);
  std::vector<double> u(model.dof_count()), before(u.size()), after(u.size());
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = 0.05 * std::sin(0.3 * i);
  assembler.assemble(u, before, nullptr);
  ASSERT_EQ(adaptivity.update(u, 1), model.cell_count());
  assembler.assemble(u, after, nullptr);
  // Weight 0: the switch itself changes nothing (to round-off: before, the
  // Hooke forces came from the folded linear part; now from each kernel).
  for (std::size_t i = 0; i < u.size(); ++i) EXPECT_NEAR(after[i], before[i], 1e-12 * (1 + std::abs(before[i])));
  std::vector<double> previous = after, current(u.size());
  for (int step = 0; step < 4; ++step) {
    adaptivity.advance_blends();
    assembler.assemble(u, current, nullptr);
    EXPECT_NE(current, previous);
    previous = current;
  }
  EXPECT_EQ(model.blend_from(0), nullptr);
  // After the blend: exactly the StVK forces.
  Scene stvk_scene = s;
  stvk_scene.model.materials[0].law = "stvk";
  const Model stvk(mesh, stvk_scene.model);
  std::vector<double> expected(u.size());
  Assembler(stvk).assemble(u, expected, nullptr);
  for (std::size_t i = 0; i < u.size(); ++i) EXPECT_NEAR(current[i], expected[i], 1e-9 * (1 + std::abs(expected[i])));
}

TEST(Adaptivity, DowngradeReturnsToTheInitialKernelExactly) {
  BeamSpec spec;
  spec.cells = {6, 2, 1};
  const Mesh mesh = make_beam(spec);
  Scene s;
  s.path = "downgrade.yaml";
  s.model.materials = {{"all", "hooke", "", 1e6, 0.3, 1000, 0}};
  s.model.fixed = {"clamp"};
  Model model(mesh, s.model);
  const Assembler assembler(model);
  AdaptivitySettings adaptive;
  adaptive.enabled = true;
  adaptive.criteria = {{"R_NL", 1e-3, 0}};
  adaptive.downgrade = true;
  adaptive.hysteresis = 0.5;
  adaptive.calm_steps = 3;
  Adaptivity adaptivity(adaptive, model, assembler);
  std::vector<double> bent(model.dof_count()), rest(model.dof_count(), 0.0);
  for (std::size_t i = 0; i < bent.size(); ++i) bent[i] = 0.2 * std::sin(0.3 * i);
  std::vector<const tm_kernel*> initial;
  for (int cell = 0; cell < model.cell_count(); ++cell) initial.push_back(&model.kernel(cell));
  EXPECT_GT(adaptivity.update(bent, 1), 0);
  EXPECT_EQ(adaptivity.update(rest, 2), 0);  // calm for 1 evaluation
  EXPECT_EQ(adaptivity.update(rest, 3), 0);  // 2
  EXPECT_GT(adaptivity.update(rest, 4), 0);  // 3: back to Hooke
  for (int cell = 0; cell < model.cell_count(); ++cell) EXPECT_EQ(&model.kernel(cell), initial[cell]);
}

}  // namespace
}  // namespace tensormass
