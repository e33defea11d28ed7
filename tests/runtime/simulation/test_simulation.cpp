// The stepping Simulation (simulation.cpp): stepping one call at a time
// gives run_scene's bits for every integrator (with the adaptive model's
// repeated load steps too), a mesh given in memory runs like the same mesh
// read from its file, and laws and boundary conditions changed between
// steps take effect, with clear errors that change nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "support/cantilever.hpp"
#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/gmsh_writer.hpp"
#include "tensormass/model/model.hpp"
#include "tensormass/simulation/simulation.hpp"

namespace tensormass {
namespace {

namespace fs = std::filesystem;
using test_support::expect_contains;

class SteppedBeam : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<test_support::TempDir>();
    io::write_msh((dir_->path() / "beam.msh").string(), test::beam(2, "quad4", {12, 3, 1}));
  }
  static void TearDownTestSuite() { dir_.reset(); }

  /// A soft clamped beam; `name` picks its output directory.
  static Scene scene(const std::string& name, const std::string& law, SolverType type) {
    Scene s = test::cantilever(law, type);
    s.path = (dir_->path() / "scene.yaml").string();
    s.mesh = (dir_->path() / "beam.msh").string();
    s.model.materials[0].constants["young"] = 1e7;
    s.solver.load_steps = 4;
    if (type != SolverType::static_newton) {
      s.solver.steps = 12;
      s.solver.dt = type == SolverType::explicit_euler ? 2e-4 : 0.01;
      s.solver.damping_mass = 2.0;
    }
    s.output.directory = (dir_->path() / name).string();
    s.output.every = 5;
    return s;
  }

  static RunOptions quiet() { return RunOptions{false, false}; }

  /// Steps one call at a time; returns the steps taken.
  static int step_through(Simulation& simulation) {
    int steps = 0;
    while (simulation.step()) ++steps;
    return steps;
  }

  static inline std::unique_ptr<test_support::TempDir> dir_;
};

void expect_same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << "dof " << i;
}

TEST_F(SteppedBeam, SteppingEqualsWholeRunForEveryIntegrator) {
  for (SolverType type : {SolverType::static_newton, SolverType::implicit_euler, SolverType::explicit_euler}) {
    SCOPED_TRACE(solver_type_name(type));
    const std::string name(solver_type_name(type));
    const RunReport whole = run_scene(scene("whole-" + name, "stvk", type), quiet());
    Scene stepped_scene = scene("stepped-" + name, "stvk", type);
    Simulation simulation(stepped_scene, quiet());
    EXPECT_EQ(step_through(simulation), stepped_scene.solver.total_steps());
    EXPECT_TRUE(simulation.finished());
    EXPECT_FALSE(simulation.step());
    expect_same_bits(simulation.state().displacement, whole.state.displacement);
    expect_same_bits(simulation.state().velocity, whole.state.velocity);
    EXPECT_EQ(simulation.report().files, whole.files);
    EXPECT_TRUE(fs::exists(fs::path(stepped_scene.output.directory) / "final.vtu"));
    EXPECT_TRUE(fs::exists(fs::path(stepped_scene.output.directory) / "summary.json"));
  }
}

TEST_F(SteppedBeam, PeakMemoryIsReportedPerPhase) {
  const RunReport report = run_scene(scene("memory", "stvk", SolverType::implicit_euler), quiet());
  const std::vector<std::string> expected{"mesh", "model and assembler", "shared", "solver", "first step", "end"};
  ASSERT_EQ(report.peak_memory_mib_by_phase.size(), expected.size());
  double before = 0.0;
  for (std::size_t p = 0; p < expected.size(); ++p) {
    const auto& [phase, per_rank] = report.peak_memory_mib_by_phase[p];
    EXPECT_EQ(phase, expected[p]);
    ASSERT_EQ(per_rank.size(), 1u);
    EXPECT_GE(per_rank[0], before) << phase;  // a peak never falls
    before = per_rank[0];
  }
  EXPECT_GT(before, 0.0);
  EXPECT_EQ(report.peak_memory_mib_by_phase.back().second, report.peak_memory_mib);
}

TEST_F(SteppedBeam, SteppingEqualsWholeRunWhenLoadStepsAreSolvedAgain) {
  auto adaptive = [&](const std::string& name) {
    Scene s = scene(name, "hooke", SolverType::static_newton);
    s.adaptivity.enabled = true;
    s.adaptivity.criteria = {{"R_NL", 0.002, 0, ""}};
    return s;
  };
  const RunReport whole = run_scene(adaptive("adaptive-whole"), quiet());
  // Cells switched after a load step, which was then solved again.
  ASSERT_TRUE(std::any_of(whole.adaptivity.listed.begin(), whole.adaptivity.listed.end(),
                          [](const AdaptivityRecord& r) { return r.step > 0 && r.upgrades > 0; }));
  Simulation simulation(adaptive("adaptive-stepped"), quiet());
  EXPECT_EQ(step_through(simulation), 4);
  expect_same_bits(simulation.state().displacement, whole.state.displacement);
  EXPECT_EQ(simulation.report().switches, whole.switches);
  const auto criteria = simulation.criteria();
  ASSERT_EQ(criteria.size(), 1u);
  EXPECT_EQ(criteria[0].first, "R_NL");
  EXPECT_EQ(criteria[0].second.size(), static_cast<std::size_t>(simulation.model().cell_count()));
  EXPECT_GT(*std::max_element(criteria[0].second.begin(), criteria[0].second.end()), 0.002);
}

TEST_F(SteppedBeam, MeshInMemoryRunsLikeItsFile) {
  const Scene from_file = scene("from-file", "stvk", SolverType::implicit_euler);
  const RunReport whole = run_scene(from_file, quiet());
  Scene in_memory = scene("in-memory", "stvk", SolverType::implicit_euler);
  in_memory.mesh = "beam made in code";
  Simulation simulation(in_memory, test::beam(2, "quad4", {12, 3, 1}), quiet());
  step_through(simulation);
  expect_same_bits(simulation.state().displacement, whole.state.displacement);
}

TEST_F(SteppedBeam, SetLawBeforeTheFirstStepRunsTheNewLaw) {
  const RunReport stvk = run_scene(scene("pure-stvk", "stvk", SolverType::implicit_euler), quiet());
  const RunReport hooke = run_scene(scene("pure-hooke", "hooke", SolverType::implicit_euler), quiet());
  Simulation simulation(scene("hooke-to-stvk", "hooke", SolverType::implicit_euler), quiet());
  std::vector<int> every_cell(simulation.model().cell_count());
  for (int cell = 0; cell < simulation.model().cell_count(); ++cell) every_cell[cell] = cell;
  simulation.set_law(every_cell, "stvk");
  EXPECT_EQ(simulation.model().kernel(0).law, std::string("stvk"));
  step_through(simulation);
  double scale = 0, to_stvk = 0, to_hooke = 0;
  for (std::size_t i = 0; i < stvk.state.displacement.size(); ++i) {
    scale = std::max(scale, std::abs(stvk.state.displacement[i]));
    to_stvk = std::max(to_stvk, std::abs(simulation.state().displacement[i] - stvk.state.displacement[i]));
    to_hooke = std::max(to_hooke, std::abs(stvk.state.displacement[i] - hooke.state.displacement[i]));
  }
  EXPECT_LE(to_stvk, 1e-12 * scale);
  EXPECT_GT(to_hooke, 1e-3 * scale);  // the laws differ visibly here: the test can fail
}

TEST_F(SteppedBeam, SetLawErrorsNameTheCellAndChangeNothing) {
  Simulation simulation(scene("law-errors", "hooke", SolverType::implicit_euler), quiet());
  const int cells = simulation.model().cell_count();
  try {
    simulation.set_law({0, cells}, "stvk");
    FAIL() << "a cell out of range was accepted";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"cell " + std::to_string(cells), "0.." + std::to_string(cells - 1)});
  }
  EXPECT_EQ(simulation.model().kernel(0).law, std::string("hooke"));
  try {
    simulation.set_law({0}, "no_such_law");
    FAIL() << "an unknown law was accepted";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"no_such_law", "quad4"});
  }
}

TEST_F(SteppedBeam, SetPrescribedHoldsTheGroupFromTheNextStep) {
  Scene s = scene("held-tip", "stvk", SolverType::implicit_euler);
  PrescribedSpec tip;
  tip.region = "tip";
  tip.displacement = {0, -0.05, 0};
  tip.profile.kind = ProfileKind::ramp;
  tip.profile.duration = 1.0;
  s.model.prescribed = {tip};
  s.model.loads.gravity = {0, 0, 0};
  Simulation simulation(s, quiet());
  ASSERT_TRUE(simulation.step());
  const Group& group = *simulation.mesh().group("tip");
  const int node = group.nodes.front();
  EXPECT_DOUBLE_EQ(simulation.state().displacement[2 * node + 1], -0.05 * 0.01);  // the ramp at t = 0.01
  simulation.set_prescribed("tip", {0.02, -0.1, 0}, {true, true, true});
  ASSERT_TRUE(simulation.step());
  for (int n : group.nodes) {
    EXPECT_EQ(simulation.state().displacement[2 * n], 0.02);
    EXPECT_EQ(simulation.state().displacement[2 * n + 1], -0.1);
  }
  simulation.set_prescribed("tip", {0, -0.2, 0}, {false, true, false});  // x stays held at 0.02
  ASSERT_TRUE(simulation.step());
  EXPECT_EQ(simulation.state().displacement[2 * node], 0.02);
  EXPECT_EQ(simulation.state().displacement[2 * node + 1], -0.2);
}

TEST_F(SteppedBeam, SetPrescribedRefusesFreeDofsAndUnknownGroups) {
  Simulation simulation(scene("held-errors", "stvk", SolverType::implicit_euler), quiet());
  try {
    simulation.set_prescribed("tip", {0, -0.1, 0});
    FAIL() << "a free group was accepted";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"tip", "free", "fixed or prescribed"});
  }
  try {
    simulation.set_prescribed("nowhere", {0, 0, 0});
    FAIL() << "an unknown group was accepted";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"nowhere"});
  }
  for (const PrescribedDof& p : simulation.model().prescribed()) EXPECT_FALSE(p.held);
}

}  // namespace
}  // namespace tensormass

namespace tensormass {
namespace {

TEST_F(SteppedBeam, AdaptiveModelGoesOnFromLawsSetByScript) {
  // Every cell put on the top rung by the script; with a huge threshold and
  // downgrade on, each is calm and descends after calm_steps evaluations:
  // the adaptive model sees the laws the script set.
  Scene s = scene("script-then-adaptive", "hooke", SolverType::implicit_euler);
  s.adaptivity.enabled = true;
  s.adaptivity.criteria = {{"R_NL", 1e9, 0, ""}};
  s.adaptivity.downgrade = true;
  s.adaptivity.calm_steps = 3;
  Simulation simulation(s, quiet());
  std::vector<int> every_cell(simulation.model().cell_count());
  for (int cell = 0; cell < simulation.model().cell_count(); ++cell) every_cell[cell] = cell;
  simulation.set_law(every_cell, "stvk");
  for (int step = 0; step < 2; ++step) ASSERT_TRUE(simulation.step());
  EXPECT_EQ(simulation.model().kernel(0).law, std::string("stvk"));  // calm twice: not yet
  ASSERT_TRUE(simulation.step());
  for (int cell = 0; cell < simulation.model().cell_count(); ++cell)
    ASSERT_EQ(simulation.model().kernel(cell).law, std::string("hooke")) << "cell " << cell;
  EXPECT_EQ(simulation.report().switches, 0);  // the report is filled at the end
  while (simulation.step()) {
  }
  EXPECT_EQ(simulation.report().switches, simulation.model().cell_count());
}

}  // namespace
}  // namespace tensormass

namespace tensormass {
namespace {

/// The viscous history stays with the cells it was built on: what would
/// move cells or their laws is refused with a message, before any step.
class ViscousBeam : public SteppedBeam {
 protected:
  static Scene viscous(const std::string& name) {
    Scene s = scene(name, "viscoelastic_neohookean", SolverType::implicit_euler);
    s.model.materials[0].constants = {{"mu", 3e6}, {"kappa", 8e6}, {"g1", 0.3}, {"tau1", 0.05},
                                      {"g2", 0.2}, {"tau2", 0.5},  {"k1", 0.1}, {"k2", 0.0}};
    return s;
  }
};

TEST_F(ViscousBeam, RunsAndRefusesTheAdaptiveModelAndLawSwitches) {
  Simulation simulation(viscous("viscous-beam"), quiet());
  EXPECT_EQ(step_through(simulation), 12);
  EXPECT_FALSE(simulation.state().viscous_history.empty());
  try {
    simulation.set_law({0}, "neohookean");
    FAIL() << "a law switch of a viscoelastic model was accepted";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"set_law", "viscoelastic"});
  }
  Scene adaptive = viscous("viscous-adaptive");
  adaptive.adaptivity.enabled = true;
  try {
    Simulation refused(adaptive, quiet());
    FAIL() << "the adaptive model was accepted on a viscoelastic law";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"scene.yaml", "viscoelastic law", "adaptive model"});
  }
}

}  // namespace
}  // namespace tensormass
