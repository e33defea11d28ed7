// Refinement during a run (adaptivity.refine) through Simulation:
// a static plate with a probe refines where R_ZZ is high and gets closer to
// the uniformly refined mesh's solution, every frame is a conforming mesh
// with its `level` field; a dynamic run refines as a probe goes in and
// coarsens as it comes back out; an explicit run refines with its stable
// step estimated again. With law switching
// on as well (ladder hooke -> neohookean), the children of an upgraded cell
// have the upgraded law right after the change, the folded assembly follows
// the carried laws, and a static run refines, switches and converges.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/test_support.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/mesh/mesh_conformity.hpp"
#include "tensormass/meshing/beam.hpp"
#include "tensormass/refinement/hierarchical_mesh.hpp"
#include "tensormass/simulation/simulation.hpp"

namespace tensormass {
namespace {

using test_support::expect_contains;
using test_support::TempDir;

constexpr double kWidth = 0.1, kHeight = 0.05;

/// bench/refine_bench.cpp's plate: 10 x 5 cm, `cells` quads across, the
/// bottom fixed, a 2 cm probe in the middle of the top.
Mesh plate_mesh(int cells) {
  BeamSpec spec;
  spec.dim = 2;
  spec.cells = {cells, cells / 2, 1};
  spec.size = {kWidth, kHeight, 1.0};
  spec.phases = {{"quad4", 1.0}};
  Mesh mesh = make_beam(spec);
  const double eps = 1e-9;
  mesh.add_node_group("bottom", [&](double, double y, double) { return y < eps; });
  mesh.add_node_group(
      "probe", [&](double x, double y, double) { return y > kHeight - eps && std::abs(x - kWidth / 2) <= 0.01 + eps; });
  return mesh;
}

/// Hooke, bottom fixed, the probe pushed 5 mm down; refinement off.
Scene plate_scene(const TempDir& dir, const std::string& name) {
  Scene scene;
  scene.path = dir.file("plate.yaml");
  scene.mesh = "plate.msh";
  MaterialSpec material;
  material.law = "hooke";
  material.constants = elastic_constants(5e3, 0.45);
  material.density = 1000;
  scene.model.materials = {material};
  scene.model.fixed = {"bottom"};
  PrescribedSpec probe;
  probe.region = "probe";
  probe.displacement = {0.0, -0.005, 0.0};
  probe.profile.kind = ProfileKind::ramp;
  probe.profile.duration = 1.0;
  scene.model.prescribed = {probe};
  scene.solver.type = SolverType::static_newton;
  scene.solver.load_steps = 1;
  scene.output.directory = dir.file(name);
  scene.output.every = 1;
  return scene;
}

RefinementSettings refine(double threshold) {
  RefinementSettings settings;
  settings.enabled = true;
  settings.threshold = threshold;
  settings.max_level = 2;
  return settings;
}

RunOptions quiet() { return RunOptions{false, false}; }

/// Largest displacement difference at the first `nodes` nodes.
double error_at(const std::vector<double>& u, const std::vector<double>& reference, int nodes) {
  double worst = 0;
  for (int node = 0; node < nodes; ++node)
    worst = std::max(worst, std::hypot(u[2 * node] - reference[2 * node], u[2 * node + 1] - reference[2 * node + 1]));
  return worst;
}

/// Conforming: no edge used by three cells, and every edge used by one
/// cell lies on the plate's outline (a hanging node would leave one inside).
void expect_conforming_plate(const Mesh& mesh, const std::string& what) {
  const ConformityReport report = check_conformity(mesh);
  EXPECT_EQ(report.overused_faces, 0) << what;
  const auto on_outline = [&](int node) {
    const double x = mesh.rest_positions[3 * node], y = mesh.rest_positions[3 * node + 1];
    return std::min({std::abs(x), std::abs(x - kWidth), std::abs(y), std::abs(y - kHeight)}) < 1e-12;
  };
  for (const std::vector<int>& edge : report.boundary_faces)
    EXPECT_TRUE(on_outline(edge[0]) && on_outline(edge[1]) &&
                (std::abs(mesh.rest_positions[3 * edge[0]] - mesh.rest_positions[3 * edge[1]]) < 1e-12 ||
                 std::abs(mesh.rest_positions[3 * edge[0] + 1] - mesh.rest_positions[3 * edge[1] + 1]) < 1e-12))
        << what << ": edge " << edge[0] << "-" << edge[1] << " is used by one cell inside the plate";
}

TEST(RefinementRun, StaticPlateRefinesTowardTheUniformlyRefinedSolution) {
  TempDir dir;
  const Mesh coarse = plate_mesh(10);
  // The reference: every cell refined twice.
  HierarchicalMesh uniform(coarse);
  for (int level = 0; level < 2; ++level) {
    std::vector<int> every(uniform.leaf_mesh().cell_count());
    for (std::size_t cell = 0; cell < every.size(); ++cell) every[cell] = static_cast<int>(cell);
    uniform.refine(every);
  }
  const RunReport fine = Simulation(plate_scene(dir, "fine"), uniform.leaf_mesh(), quiet()).run();
  const RunReport plain = Simulation(plate_scene(dir, "coarse"), coarse, quiet()).run();

  Scene scene = plate_scene(dir, "refined");
  scene.refinement = refine(0.3);
  Simulation simulation(scene, coarse, quiet());
  const RunReport& refined = simulation.run();

  EXPECT_GT(refined.cells, coarse.cell_count());
  EXPECT_LT(refined.cells, uniform.leaf_mesh().cell_count());
  EXPECT_EQ(simulation.mesh().cell_count(), refined.cells);
  EXPECT_EQ(static_cast<int>(refined.state.displacement.size()), 2 * simulation.mesh().node_count());
  ASSERT_GE(refined.refinement.size(), 2u);  // the start and at least one refinement
  EXPECT_EQ(refined.refinement.front().cells, coarse.cell_count());
  EXPECT_EQ(refined.refinement.back().cells, refined.cells);
  EXPECT_EQ(refined.statistics.newton_per_step.size(), 1u);  // re-solves count with their load step
  EXPECT_TRUE(refined.statistics.warnings.empty());

  const double coarse_error = error_at(plain.state.displacement, fine.state.displacement, coarse.node_count());
  const double refined_error = error_at(refined.state.displacement, fine.state.displacement, coarse.node_count());
  EXPECT_LT(refined_error, 0.4 * coarse_error) << "coarse " << coarse_error << ", refined " << refined_error;

  // Every frame is its own conforming mesh with the levels; final.vtu too.
  for (const std::string name : {"frame_000001.vtu", "final.vtu"}) {
    const std::string path = (dir.path() / "refined" / name).string();
    expect_conforming_plate(read_mesh(path), name);
    EXPECT_NE(test_support::read_file(path).find("Name=\"level\""), std::string::npos) << name;
  }
  EXPECT_EQ(read_mesh((dir.path() / "refined" / "final.vtu").string()).cell_count(), refined.cells);
  EXPECT_EQ(test_support::read_file(dir.path() / "coarse" / "final.vtu").find("Name=\"level\""), std::string::npos);
  const std::string summary = test_support::read_file(dir.path() / "refined" / "summary.json");
  const auto refinement = nlohmann::json::parse(summary)["refinement"];
  EXPECT_EQ(refinement["criterion"], "R_ZZ");
  EXPECT_EQ(refinement["events"][0]["leaves_per_level"], nlohmann::json::array({50})) << refinement.dump(2);
}

TEST(RefinementRun, DynamicProbeRefinesThenCoarsensBack) {
  TempDir dir;
  const Mesh coarse = plate_mesh(10);
  Scene scene = plate_scene(dir, "dynamic");
  scene.solver.load_steps = 1;
  // The probe goes 5 mm in and comes back out (a sinusoid over 0.4 s), then
  // 0.8 s in 40 implicit steps. Once the probe comes out the mesh only coarsens:
  // a parent merged back is calm too, so no cell is split again.
  scene.model.prescribed[0].profile.kind = ProfileKind::sinusoid;
  scene.model.prescribed[0].profile.period = 0.8;
  scene.model.prescribed[0].profile.phase = 0;
  scene.solver.type = SolverType::implicit_euler;
  scene.solver.dt = 0.02;
  scene.solver.steps = 40;
  scene.solver.damping_mass = 20.0;
  scene.output.every = 10;
  scene.refinement = refine(0.3);
  scene.refinement.every = 1;
  scene.refinement.calm_steps = 1;
  Simulation simulation(scene, coarse, quiet());
  const RunReport& report = simulation.run();
  EXPECT_TRUE(simulation.finished());
  EXPECT_EQ(report.statistics.step_ms.size(), 40u);
  int most = 0;
  for (const RefinementRecord& event : report.refinement) most = std::max(most, event.cells);
  ASSERT_GE(report.refinement.size(), 3u);
  EXPECT_GT(most, coarse.cell_count());  // cells were added
  const auto peak = std::find_if(report.refinement.begin(), report.refinement.end(),
                                 [&](const RefinementRecord& event) { return event.cells == most; });
  for (auto event = peak; event + 1 != report.refinement.end(); ++event)
    EXPECT_LE((event + 1)->cells, event->cells) << "step " << (event + 1)->step << ": split again after coarsening";
  EXPECT_EQ(report.refinement.back().cells, coarse.cell_count());  // then removed, back to the original cells
  EXPECT_EQ(report.cells, report.refinement.back().cells);
  for (const std::string name : {"frame_000010.vtu", "frame_000020.vtu", "frame_000040.vtu", "final.vtu"})
    expect_conforming_plate(read_mesh((dir.path() / "dynamic" / name).string()), name);
}

TEST(RefinementRun, ExplicitRunRefinesAndKeepsAStableStep) {
  // The probe pressed 2 mm in over 0.1 s, symplectic Euler with a step
  // below the refined cells' stable one: the integrator is rebuilt after
  // each change (estimating the stable step again) and the run stays bounded.
  TempDir dir;
  const Mesh coarse = plate_mesh(10);
  Scene scene = plate_scene(dir, "explicit");
  scene.model.prescribed[0].displacement = {0.0, -0.002, 0.0};
  scene.model.prescribed[0].profile.duration = 0.1;
  scene.solver.type = SolverType::explicit_euler;
  scene.solver.dt = 1e-4;
  scene.solver.steps = 1000;
  scene.solver.damping_mass = 20.0;
  scene.output.every = 0;
  scene.refinement = refine(0.3);
  scene.refinement.every = 100;
  Simulation simulation(scene, coarse, quiet());
  const RunReport& report = simulation.run();
  EXPECT_TRUE(simulation.finished());
  ASSERT_GE(report.refinement.size(), 2u);
  EXPECT_GT(report.refinement.back().cells, coarse.cell_count());
  EXPECT_GT(report.statistics.stable_dt, scene.solver.dt);  // re-estimated on the final, refined mesh
  for (const std::string& warning : report.statistics.warnings) EXPECT_EQ(warning.find("exceeds"), std::string::npos);
  double largest = 0;
  for (double u : simulation.state().displacement) largest = std::max(largest, std::abs(u));
  EXPECT_LT(largest, 0.01);  // bounded: 2 mm pushed in, no blow-up
  expect_conforming_plate(read_mesh((dir.path() / "explicit" / "final.vtu").string()), "final.vtu");
}

/// Law switching on R_NL, one rung from Hooke to neo-Hookean, no downgrade.
AdaptivitySettings hooke_to_neohookean(double threshold) {
  AdaptivitySettings settings;
  settings.enabled = true;
  CriterionSpec criterion;
  criterion.name = "R_NL";
  criterion.threshold = threshold;
  settings.criteria = {criterion};
  settings.ladder = {"hooke", "neohookean"};
  return settings;
}

/// The rest corners of every cell of a 2D model.
std::vector<std::vector<std::array<double, 2>>> cell_corners(const Model& model) {
  std::vector<std::vector<std::array<double, 2>>> corners(static_cast<std::size_t>(model.cell_count()));
  const std::vector<double>& x = model.mesh().rest_positions;
  for (int cell = 0; cell < model.cell_count(); ++cell)
    for (int node : model.cell_nodes(cell)) corners[cell].push_back({x[3 * node], x[3 * node + 1]});
  return corners;
}

std::array<double, 2> centroid(const std::vector<std::array<double, 2>>& corners) {
  std::array<double, 2> c{0, 0};
  for (const auto& p : corners) c[0] += p[0] / corners.size(), c[1] += p[1] / corners.size();
  return c;
}

/// Whether p lies inside the convex polygon (either orientation).
bool inside(const std::vector<std::array<double, 2>>& polygon, const std::array<double, 2>& p) {
  bool positive = false, negative = false;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const auto& a = polygon[i];
    const auto& b = polygon[(i + 1) % polygon.size()];
    const double cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
    positive = positive || cross > 1e-15;
    negative = negative || cross < -1e-15;
  }
  return !(positive && negative);
}

/// Largest |a - b| over the largest |b|.
double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double diff = 0, size = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff = std::max(diff, std::abs(a[i] - b[i]));
  for (double v : b) size = std::max(size, std::abs(v));
  return size > 0 ? diff / size : diff;
}

int cells_under(const Model& model, const std::string& law) {
  int count = 0;
  for (int cell = 0; cell < model.cell_count(); ++cell) count += std::string(model.kernel(cell).law) == law;
  return count;
}

TEST(RefinementRun, DynamicRefinementWithLawSwitchingCarriesLawsToChildren) {
  TempDir dir;
  const Mesh coarse = plate_mesh(10);
  Scene scene = plate_scene(dir, "both");
  // The probe goes 5 mm in over 0.2 s (a quarter of a sinusoid): 20 implicit steps.
  scene.model.prescribed[0].profile.kind = ProfileKind::sinusoid;
  scene.model.prescribed[0].profile.period = 0.8;
  scene.model.prescribed[0].profile.phase = 0;
  scene.solver.type = SolverType::implicit_euler;
  scene.solver.dt = 0.01;
  scene.solver.steps = 20;
  scene.solver.damping_mass = 20.0;
  scene.output.every = 5;
  scene.refinement = refine(0.3);
  scene.refinement.every = 5;
  scene.refinement.coarsen = false;               // children lie inside the cell they come from (checked below)
  scene.adaptivity = hooke_to_neohookean(0.002);  // cells climb from step 10, between the mesh changes
  Simulation simulation(scene, coarse, quiet());
  int changes = 0, children_checked = 0;
  while (!simulation.finished()) {
    const auto before = cell_corners(simulation.model());
    std::vector<std::string> laws;
    for (int cell = 0; cell < simulation.model().cell_count(); ++cell)
      laws.emplace_back(simulation.model().kernel(cell).law);
    const std::size_t events = simulation.report().refinement.size();
    simulation.step();
    if (simulation.report().refinement.size() == events) continue;
    ++changes;
    // Without downgrade, an upgraded cell stays upgraded through the step:
    // every new cell inside an old neo-Hookean quad (a refined cell's
    // children, or the quad itself) must be neo-Hookean. (A cell that
    // replaces several transition triangles takes the first one's law.)
    const Model& model = simulation.model();
    const auto after = cell_corners(model);
    for (int cell = 0; cell < model.cell_count(); ++cell) {
      const std::array<double, 2> c = centroid(after[cell]);
      const auto source = std::find_if(before.begin(), before.end(), [&](const auto& old) { return inside(old, c); });
      ASSERT_NE(source, before.end()) << "cell " << cell << " lies in no old cell";
      if (source->size() != 4 || laws[source - before.begin()] != "neohookean") continue;
      ++children_checked;
      EXPECT_STREQ(model.kernel(cell).law, "neohookean") << "step " << simulation.state().step << ", cell " << cell;
    }
    // The rebuilt assembler folds the Hooke cells under the carried laws:
    // its forces are those of the per-cell assembly.
    const Assembler per_cell(model, false);
    std::vector<double> expected(model.dof_count(), 0.0);
    per_cell.assemble(simulation.state().displacement, expected, nullptr);
    EXPECT_LT(relative_difference(simulation.internal_force(), expected), 1e-10) << "step " << simulation.state().step;
  }
  const RunReport& report = simulation.report();
  EXPECT_EQ(report.statistics.step_ms.size(), 20u);
  EXPECT_GT(changes, 0);
  EXPECT_GT(children_checked, 0) << "no cell had climbed before a mesh change";
  EXPECT_GT(report.cells, coarse.cell_count());
  EXPECT_GT(report.switches, 0);
  EXPECT_GT(cells_under(simulation.model(), "neohookean"), 0);
  EXPECT_GT(cells_under(simulation.model(), "hooke"), 0);
  const std::string summary = test_support::read_file(dir.path() / "both" / "summary.json");
  const auto json = nlohmann::json::parse(summary);
  EXPECT_EQ(json["adaptivity"]["criteria"][0]["name"], "R_NL");
  EXPECT_FALSE(json["adaptivity"]["per_step"].empty());
  EXPECT_EQ(json["refinement"]["criterion"], "R_ZZ");
  EXPECT_FALSE(json["refinement"]["events"].empty());
  EXPECT_TRUE(json["elements_per_law"].contains("neohookean")) << summary;
  // The frames hold the laws of their mesh: law_id on every cell of the last one.
  const std::string frame = test_support::read_file(dir.path() / "both" / "frame_000020.vtu");
  EXPECT_NE(frame.find("Name=\"law_id\""), std::string::npos);
  EXPECT_EQ(read_mesh((dir.path() / "both" / "frame_000020.vtu").string()).cell_count(), report.cells);
}

TEST(RefinementRun, StaticPlateRefinesAndSwitchesLawsThenConverges) {
  TempDir dir;
  const Mesh coarse = plate_mesh(10);
  Scene scene = plate_scene(dir, "static_both");
  // Ten load steps (two to four ran into cells inverted at a load step's
  // start before the predictor fell back and the increment was cut: the
  // test below).
  scene.solver.load_steps = 10;
  scene.refinement = refine(0.3);
  scene.adaptivity = hooke_to_neohookean(0.01);
  Simulation simulation(scene, coarse, quiet());
  const RunReport& report = simulation.run();
  EXPECT_TRUE(simulation.finished());
  EXPECT_EQ(report.statistics.newton_per_step.size(), 10u);  // re-solves count with their load step
  EXPECT_TRUE(report.statistics.warnings.empty()) << report.statistics.warnings.front();
  EXPECT_GT(report.cells, coarse.cell_count());
  EXPECT_GE(report.refinement.size(), 2u);
  EXPECT_GT(report.switches, 0);
  const Model& model = simulation.model();
  EXPECT_GT(cells_under(model, "neohookean"), 0);
  EXPECT_GT(cells_under(model, "hooke"), 0);
  // In equilibrium on the final mesh under the final laws: the forces at the
  // free dofs are round-off next to the reactions.
  const std::vector<double> force = simulation.internal_force();
  double free = 0, all = 0;
  for (int dof : model.free_dofs()) free = std::max(free, std::abs(force[dof]));
  for (double f : force) all = std::max(all, std::abs(f));
  EXPECT_GT(all, 0);
  EXPECT_LT(free, 1e-6 * all);
}

/// The largest force at a free dof over the largest force: round-off in equilibrium.
double free_force_share(const Simulation& simulation) {
  const std::vector<double> force = simulation.internal_force();
  double free = 0, all = 0;
  for (int dof : simulation.model().free_dofs()) free = std::max(free, std::abs(force[dof]));
  for (double f : force) all = std::max(all, std::abs(f));
  return all > 0 ? free / all : 1.0;
}

// Settings next to the test above's on which static Newton met tangents
// that are not positive definite (compressed neo-Hookean cells right after
// a law switch or a refinement) and failed before its shifted steps: a
// sparse Cholesky failure at the re-solve's first tangent (CI on an AVX2
// machine with the test above's settings), or Newton wandering on steps
// that an indefinite LDL^T solve made uphill. Each converges now.
TEST(RefinementRun, StaticPlateConvergesThroughIndefiniteTangents) {
  const Mesh coarse = plate_mesh(10);
  struct Case {
    double linear_tolerance, refine_threshold, climb_threshold;
  };
  for (const Case& c : {Case{1e-6, 0.3, 0.012}, Case{1e-10, 0.28, 0.01}, Case{1e-5, 0.28, 0.008},
                        Case{3e-6, 0.29, 0.01}, Case{1e-6, 0.28, 0.02}, Case{1e-4, 0.27, 0.02}}) {
    SCOPED_TRACE(testing::Message() << "linear tolerance " << c.linear_tolerance << ", R_ZZ " << c.refine_threshold
                                    << ", R_NL " << c.climb_threshold);
    TempDir dir;
    Scene scene = plate_scene(dir, "static_both");
    scene.solver.load_steps = 10;
    scene.solver.linear.tolerance = c.linear_tolerance;
    scene.refinement = refine(c.refine_threshold);
    scene.adaptivity = hooke_to_neohookean(c.climb_threshold);
    Simulation simulation(scene, coarse, quiet());
    const RunReport& report = simulation.run();
    EXPECT_TRUE(simulation.finished());
    EXPECT_TRUE(report.statistics.warnings.empty()) << report.statistics.warnings.front();
    EXPECT_GT(report.switches, 0);
    EXPECT_LT(free_force_share(simulation), 1e-6);
  }
}

// Few load steps on the refining plate: the predicted start of a load step
// (extrapolated, or the last state with the probe moved on) inverts a small
// cell at the probe's corner, whose neo-Hookean residual is then NaN. The
// start falls back to a lower-order prediction, then the load increment is
// halved; each of these stopped at "the residual ... is not finite" before.
TEST(RefinementRun, StaticPlateCutsLoadStepsWhoseStartInvertsACell) {
  const Mesh coarse = plate_mesh(10);
  struct Case {
    bool adaptive;
    int load_steps;
  };
  for (const Case& c : {Case{false, 2}, Case{true, 2}, Case{true, 3}, Case{true, 4}}) {
    SCOPED_TRACE(testing::Message() << (c.adaptive ? "hooke -> neohookean, " : "neohookean, ") << c.load_steps
                                    << " load steps");
    TempDir dir;
    Scene scene = plate_scene(dir, "cut");
    scene.solver.load_steps = c.load_steps;
    scene.refinement = refine(0.3);
    if (c.adaptive) scene.adaptivity = hooke_to_neohookean(0.01);
    else scene.model.materials[0].law = "neohookean";
    Simulation simulation(scene, coarse, quiet());
    const RunReport& report = simulation.run();
    EXPECT_TRUE(simulation.finished());
    EXPECT_EQ(report.statistics.newton_per_step.size(), static_cast<std::size_t>(c.load_steps));
    EXPECT_TRUE(report.statistics.warnings.empty()) << report.statistics.warnings.front();
    EXPECT_GT(report.cells, coarse.cell_count());
    EXPECT_LT(free_force_share(simulation), 1e-6);
  }
}

}  // namespace
}  // namespace tensormass
