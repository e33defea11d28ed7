// The adaptive model end to end (run_scene on a 2D beam): limits of the
// threshold, accuracy in between, blending continuity, exact downgrade.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "support/cantilever.hpp"
#include "support/test_support.hpp"
#include "tensormass/adaptivity/adaptivity.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/common/errors.hpp"
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
    s.model.materials[0].constants["young"] = 1e7;
    s.solver.load_steps = 4;
    s.output.directory = (directory_ / ("out-" + law + criterion + std::to_string(threshold))).string();
    if (!criterion.empty()) {
      s.adaptivity.enabled = true;
      s.adaptivity.criteria = {{criterion, threshold, 0, ""}};
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

TEST_F(AdaptiveBeam, ZeroThresholdIsExactlyPureStvk) {
  const RunReport stvk = run(scene("stvk"));
  const RunReport adaptive = run(scene("hooke", "R_NL", 0.0));
  EXPECT_EQ(adaptive.switches, 150);  // all before the first load step
  ASSERT_FALSE(adaptive.adaptivity.listed.empty());
  EXPECT_EQ(adaptive.adaptivity.listed.front().step, 0);
  EXPECT_EQ(max_difference(stvk, adaptive), 0.0);
}

TEST_F(AdaptiveBeam, LadderLimitsAreExactlyTheFirstAndLastRung) {
  const RunReport first = run(scene("hooke")), last = run(scene("neohookean"));
  for (const std::string criterion : {"R_NL", "R_P"})
    for (const std::vector<std::string>& ladder :
         {std::vector<std::string>{"hooke", "neohookean"}, std::vector<std::string>{"hooke", "stvk", "neohookean"}}) {
      Scene huge = scene("hooke", criterion, 1e9), zero = scene("hooke", criterion, 0.0);
      huge.adaptivity.ladder = zero.adaptivity.ladder = ladder;
      const RunReport none = run(huge), all = run(zero);
      EXPECT_EQ(none.switches, 0) << criterion;
      EXPECT_EQ(max_difference(first, none), 0.0) << criterion << ", " << ladder.size() << " rungs";
      EXPECT_EQ(all.switches, 150 * (static_cast<int>(ladder.size()) - 1)) << criterion;
      EXPECT_EQ(max_difference(last, all), 0.0) << criterion << ", " << ladder.size() << " rungs";
    }
}

/// R_NL, and R_P (the stress Hooke gets wrong against the ladder's
/// neo-Hookean rung): in between their limits each lifts some cells and
/// halves Hooke's error.
TEST_F(AdaptiveBeam, IntermediateThresholdOnANeoHookeanLadderBeatsHooke) {
  const RunReport neohookean = run(scene("neohookean")), hooke = run(scene("hooke"));
  for (const auto& [criterion, threshold] : {std::pair<std::string, double>{"R_NL", 0.01}, {"R_P", 0.05}}) {
    Scene s = scene("hooke", criterion, threshold);
    s.adaptivity.ladder = {"hooke", "neohookean"};
    const RunReport adaptive = run(s);
    EXPECT_GT(adaptive.switches, 0) << criterion;
    EXPECT_LT(adaptive.switches, 150) << criterion;
    EXPECT_LT(max_difference(neohookean, adaptive), 0.5 * max_difference(neohookean, hooke)) << criterion;
  }
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
  ASSERT_FALSE(adaptive.adaptivity.listed.empty());
  EXPECT_EQ(adaptive.adaptivity.listed.back().upgrades, 0);
}

TEST_F(AdaptiveBeam, EveryCriterionRunsAndWritesItsField) {
  for (const std::string& name : criterion_names()) {
    Scene s = scene("hooke", name, name == "R_VL" || name == "R_VLX" ? 0.01 : 1e9);
    const RunReport report = run(s);
    EXPECT_EQ(report.switches, 0) << name;
    EXPECT_TRUE(fs::exists(fs::path(s.output.directory) / "final.vtu")) << name;
  }
}

/// A ladder's laws must compute the same constants from each material on it:
/// hooke and mooney_rivlin do not (lam, mu against c10, c01, kappa), even
/// for a material that gives both laws' constants.
TEST(Adaptivity, LadderOfLawsWithOtherConstantsIsRefused) {
  BeamSpec spec;
  spec.cells = {4, 2, 1};
  const Mesh mesh = make_beam(spec);
  Scene s;
  std::map<std::string, double> constants = elastic_constants(1e6, 0.3);
  constants.insert({{"c10", 1e5}, {"c01", 2e4}, {"kappa", 1e6}});
  s.model.source = "ladder.yaml";
  s.model.materials = {{"all", "hooke", "", constants, 1000, 7}};
  s.model.fixed = {"clamp"};
  Model model(mesh, s.model);
  const Assembler assembler(model);
  AdaptivitySettings adaptive;
  adaptive.enabled = true;
  adaptive.criteria = {{"R_NL", 0.01, 0, ""}};
  adaptive.ladder = {"hooke", "mooney_rivlin"};
  try {
    Adaptivity adaptivity(adaptive, model, assembler);
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("ladder.yaml:7: material 0"), std::string::npos) << message;
    EXPECT_NE(message.find("hooke and mooney_rivlin do not compute the same constants"), std::string::npos) << message;
  }
  adaptive.ladder = {"hooke", "stvk"};
  EXPECT_NO_THROW(Adaptivity(adaptive, model, assembler));
}

TEST(Adaptivity, BlendingStartsWithoutAJumpAndReachesTheNewLaw) {
  BeamSpec spec;
  spec.cells = {6, 2, 1};
  const Mesh mesh = make_beam(spec);
  Scene s;
  s.path = "blend.yaml";
  MaterialSpec material{"all", "hooke", "", elastic_constants(1e6, 0.3), 1000, 0};
  s.model.materials = {material};
  s.model.fixed = {"clamp"};
  Model model(mesh, s.model);
  const Assembler assembler(model);
  AdaptivitySettings adaptive;
  adaptive.enabled = true;
  adaptive.criteria = {{"R_NL", 0.0, 0, ""}};
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

/// The laws the model's cells are under.
std::set<std::string> laws_of(const Model& model) {
  std::set<std::string> names;
  for (int cell = 0; cell < model.cell_count(); ++cell) names.insert(model.kernel(cell).law);
  return names;
}

/// Adaptivity on R_NL alone with a ladder (the other settings at their defaults).
AdaptivitySettings ladder_settings(double threshold, std::vector<std::string> ladder) {
  AdaptivitySettings adaptive;
  adaptive.enabled = true;
  adaptive.criteria = {{"R_NL", threshold, 0, ""}};
  adaptive.ladder = std::move(ladder);
  return adaptive;
}

TEST(Adaptivity, CellsClimbAndDescendOneRungAtATime) {
  BeamSpec spec;
  spec.cells = {6, 2, 1};
  const Mesh mesh = make_beam(spec);
  Scene s = test::cantilever("hooke");
  Model model(mesh, s.model);
  const Assembler assembler(model);
  AdaptivitySettings adaptive = ladder_settings(0.01, {"hooke", "stvk", "neohookean"});
  adaptive.downgrade = true;
  adaptive.calm_steps = 2;
  Adaptivity adaptivity(adaptive, model, assembler);
  std::vector<double> strained(model.dof_count()), rest(model.dof_count(), 0.0);
  for (std::size_t i = 0; i < strained.size(); ++i) strained[i] = 0.2 * std::sin(0.9 * i);
  auto laws = [&] { return laws_of(model); };
  EXPECT_EQ(adaptivity.start(rest), 0);
  EXPECT_EQ(adaptivity.update(strained, 1), model.cell_count());
  EXPECT_EQ(laws(), std::set<std::string>{"stvk"});
  EXPECT_EQ(adaptivity.update(strained, 2), model.cell_count());
  EXPECT_EQ(laws(), std::set<std::string>{"neohookean"});
  EXPECT_EQ(adaptivity.update(strained, 3), 0);  // the top rung
  // Calm for calm_steps evaluations: one rung down each time, never below the initial law.
  for (int step = 4; step < 12; ++step) adaptivity.update(rest, step);
  EXPECT_EQ(laws(), std::set<std::string>{"hooke"});
  for (int cell = 0; cell < model.cell_count(); ++cell) EXPECT_EQ(&model.kernel(cell), &model.initial_kernel(cell));
  EXPECT_EQ(adaptivity.total_switches(), 4 * model.cell_count());
}

TEST(Adaptivity, StartClimbsAsFarAsTheCriteriaAsk) {
  BeamSpec spec;
  spec.cells = {4, 2, 1};
  const Mesh mesh = make_beam(spec);
  Model model(mesh, test::cantilever("hooke").model);
  const Assembler assembler(model);
  AdaptivitySettings adaptive = ladder_settings(0.0, {"hooke", "stvk", "neohookean"});
  adaptive.blend_steps = 3;  // nothing to blend from before the first step
  Adaptivity adaptivity(adaptive, model, assembler);
  const std::vector<double> rest(model.dof_count(), 0.0);
  EXPECT_EQ(adaptivity.start(rest), 2 * model.cell_count());
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    EXPECT_STREQ(model.kernel(cell).law, "neohookean");
    EXPECT_EQ(model.blend_from(cell), nullptr);
  }
  ASSERT_EQ(adaptivity.records().listed.size(), 1u);
  EXPECT_EQ(adaptivity.records().listed[0].step, 0);
}

/// u = (R - I) X: a rigid rotation by `angle` about z (in the plane in 2D).
std::vector<double> rigid_rotation(const Model& model, double angle) {
  const int d = model.dim();
  std::vector<double> u(model.dof_count());
  const std::vector<double>& X = model.mesh().rest_positions;
  for (std::size_t node = 0; node < u.size() / d; ++node) {
    const double x = X[3 * node], y = X[3 * node + 1];
    u[node * d] = std::cos(angle) * x - std::sin(angle) * y - x;
    u[node * d + 1] = std::sin(angle) * x + std::cos(angle) * y - y;
  }
  return u;
}

/// Criteria with rungs: R_NL (rotation or strain) asks for corotational, R_E
/// (strain alone) for neo-Hookean, so a rotated cell stops at corotational, a
/// strained one climbs to the top and comes back to corotational, not lower,
/// while it is still rotated.
TEST(Adaptivity, EachCriterionLiftsCellsOnlyAsFarAsItsRung) {
  BeamSpec spec;
  spec.cells = {6, 2, 1};
  const Mesh mesh = make_beam(spec);
  Model model(mesh, test::cantilever("hooke").model);
  const Assembler assembler(model);
  AdaptivitySettings adaptive;
  adaptive.enabled = true;
  adaptive.ladder = {"hooke", "corotational", "neohookean"};
  adaptive.criteria = {{"R_NL", 0.01, 0, "corotational"}, {"R_E", 0.01, 0, ""}};
  adaptive.downgrade = true;
  adaptive.calm_steps = 1;
  Adaptivity adaptivity(adaptive, model, assembler);
  auto laws = [&] { return laws_of(model); };
  const std::vector<double> turned = rigid_rotation(model, 0.5), rest(model.dof_count(), 0.0);
  std::vector<double> stretched = rest;
  for (std::size_t node = 0; node < rest.size() / model.dim(); ++node)
    stretched[node * model.dim()] = 0.2 * model.mesh().rest_positions[3 * node];
  EXPECT_EQ(adaptivity.start(turned), model.cell_count());  // R_NL 0.17 fails, R_E is 0: one rung only
  EXPECT_EQ(laws(), std::set<std::string>{"corotational"});
  EXPECT_EQ(adaptivity.update(stretched, 1), model.cell_count());  // R_E 0.22
  EXPECT_EQ(laws(), std::set<std::string>{"neohookean"});
  EXPECT_EQ(adaptivity.update(turned, 2), model.cell_count());  // strain calm: down to what the rotation needs
  EXPECT_EQ(laws(), std::set<std::string>{"corotational"});
  EXPECT_EQ(adaptivity.update(turned, 3), 0);  // R_NL still fails: held at corotational
  EXPECT_EQ(adaptivity.update(rest, 4), model.cell_count());
  EXPECT_EQ(laws(), std::set<std::string>{"hooke"});
}

TEST(Adaptivity, CriterionRungMustBeALawAboveTheFirst) {
  BeamSpec spec;
  spec.cells = {2, 1, 1};
  const Mesh mesh = make_beam(spec);
  Model model(mesh, test::cantilever("hooke").model);
  const Assembler assembler(model);
  AdaptivitySettings adaptive = ladder_settings(0.01, {"hooke", "corotational", "stvk"});
  adaptive.criteria[0].rung = "hooke";
  EXPECT_THROW(Adaptivity(adaptive, model, assembler), std::invalid_argument);
  adaptive.criteria[0].rung = "neohookean";
  EXPECT_THROW(Adaptivity(adaptive, model, assembler), std::invalid_argument);
  adaptive.criteria[0].rung = "corotational";
  EXPECT_NO_THROW(Adaptivity(adaptive, model, assembler));
}

TEST(Adaptivity, LadderWithoutKernelsForTheMeshIsRefused) {
  BeamSpec spec;
  spec.cells = {2, 1, 1};
  const Mesh mesh = make_beam(spec);
  Model model(mesh, test::cantilever("hooke").model);
  const Assembler assembler(model);
  AdaptivitySettings adaptive = ladder_settings(0.01, {"hooke", "no_such_law"});
  EXPECT_THROW(Adaptivity(adaptive, model, assembler), std::invalid_argument);
  adaptive.ladder = {"hooke"};
  EXPECT_THROW(Adaptivity(adaptive, model, assembler), std::invalid_argument);
}

/// anp cells keep their split over a switch: a ladder with a law that has
/// no anp kernel (stvk) is refused before the first step, naming the
/// material, the element and the law; [hooke, neohookean] is taken.
TEST(Adaptivity, LadderWithoutKernelsOfTheCellsSplitIsRefused) {
  const Mesh mesh = test::beam(3, "tet6", {2, 1, 1});
  Scene scene = test::cantilever("hooke");
  scene.model.source = "anp.yaml";
  scene.model.materials[0].split = "anp";
  scene.model.materials[0].line = 4;
  Model model(mesh, scene.model);
  const Assembler assembler(model);
  try {
    Adaptivity adaptivity(ladder_settings(0.01, {"hooke", "stvk"}), model, assembler);
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string message = error.what();
    for (const char* part : {"anp.yaml:4: material 0", "tet4 cells use split anp", "law 'stvk' has no kernel"})
      EXPECT_NE(message.find(part), std::string::npos) << message;
  }
  EXPECT_NO_THROW(Adaptivity(ladder_settings(0.01, {"hooke", "neohookean"}), model, assembler));
}

TEST(Adaptivity, DowngradeReturnsToTheInitialKernelExactly) {
  BeamSpec spec;
  spec.cells = {6, 2, 1};
  const Mesh mesh = make_beam(spec);
  Scene s;
  s.path = "downgrade.yaml";
  s.model.materials = {{"all", "hooke", "", elastic_constants(1e6, 0.3), 1000, 0}};
  s.model.fixed = {"clamp"};
  Model model(mesh, s.model);
  const Assembler assembler(model);
  AdaptivitySettings adaptive;
  adaptive.enabled = true;
  adaptive.criteria = {{"R_NL", 1e-3, 0, ""}};
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
