// Refinement during 3D runs (adaptivity.refine on hex8 and tet4 blocks):
// a static indentation refines under the probe and gets closer
// to the uniformly refined mesh's solution; a dynamic run refines as the
// probe goes in and coarsens back to the original cells once it is out;
// with law switching on as well, the laws follow the children. Every frame
// is a conforming mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/mesh/mesh_conformity.hpp"
#include "tensormass/meshing/beam.hpp"
#include "tensormass/refinement/hierarchical_mesh.hpp"
#include "tensormass/simulation/simulation.hpp"

namespace tensormass {
namespace {

using test_support::TempDir;

constexpr double kSide = 0.08, kHeight = 0.04;

/// An 8 x 4 x 8 cm block of `cells` x cells/2 x cells cubes cut by `cut`,
/// the base fixed, a 4 x 4 cm probe in the middle of the top.
Mesh block(int cells, const char* cut) {
  BeamSpec spec;
  spec.dim = 3;
  spec.cells = {cells, cells / 2, cells};
  spec.size = {kSide, kHeight, kSide};
  spec.phases = {{cut, 1.0}};
  Mesh mesh = make_beam(spec);
  const double eps = 1e-9;
  mesh.add_node_group("base", [&](double, double y, double) { return y < eps; });
  mesh.add_node_group("probe", [&](double x, double y, double z) {
    return y > kHeight - eps && std::abs(x - kSide / 2) <= 0.02 + eps && std::abs(z - kSide / 2) <= 0.02 + eps;
  });
  return mesh;
}

/// Static Hooke (E 5 kPa, nu 0.45), the probe pushed 4 mm down in one load step.
Scene indentation(const TempDir& dir, const std::string& name) {
  Scene scene;
  scene.path = dir.file("block.yaml");
  scene.mesh = "block.msh";
  MaterialSpec material;
  material.law = "hooke";
  material.constants = elastic_constants(5e3, 0.45);
  material.density = 1000;
  scene.model.materials = {material};
  scene.model.fixed = {"base"};
  PrescribedSpec probe;
  probe.region = "probe";
  probe.displacement = {0.0, -0.004, 0.0};
  probe.profile.kind = ProfileKind::ramp;
  probe.profile.duration = 1.0;
  scene.model.prescribed = {probe};
  scene.solver.type = SolverType::static_newton;
  scene.solver.load_steps = 1;
  scene.output.directory = dir.file(name);
  scene.output.every = 1;
  return scene;
}

RefinementSettings refine(double threshold, int max_level) {
  RefinementSettings settings;
  settings.enabled = true;
  settings.threshold = threshold;
  settings.max_level = max_level;
  return settings;
}

RunOptions quiet() { return RunOptions{false, false}; }

/// Largest displacement difference at the first `nodes` nodes.
double error_at(const std::vector<double>& u, const std::vector<double>& reference, int nodes) {
  double worst = 0;
  for (int node = 0; node < nodes; ++node)
    worst = std::max(worst, std::hypot(u[3 * node] - reference[3 * node], u[3 * node + 1] - reference[3 * node + 1],
                                       u[3 * node + 2] - reference[3 * node + 2]));
  return worst;
}

/// Conforming: no face used by three cells, and every face used by one cell
/// lies on the block's surface (a hanging node would leave one inside).
void expect_conforming_block(const Mesh& mesh, const std::string& what) {
  const ConformityReport report = check_conformity(mesh);
  EXPECT_EQ(report.overused_faces, 0) << what;
  const std::array<double, 3> size{kSide, kHeight, kSide};
  for (const std::vector<int>& face : report.boundary_faces) {
    bool on_side = false;
    for (int axis = 0; axis < 3 && !on_side; ++axis)
      for (double side : {0.0, size[axis]})
        on_side = on_side || std::all_of(face.begin(), face.end(), [&](int node) {
                    return std::abs(mesh.rest_positions[3 * node + axis] - side) < 1e-12;
                  });
    ASSERT_TRUE(on_side) << what << ": a face used by one cell inside the block";
  }
}

Mesh uniformly_refined(const Mesh& coarse, int levels) {
  HierarchicalMesh uniform(coarse);
  for (int level = 0; level < levels; ++level) {
    std::vector<int> every(static_cast<std::size_t>(uniform.leaf_mesh().cell_count()));
    for (std::size_t cell = 0; cell < every.size(); ++cell) every[cell] = static_cast<int>(cell);
    uniform.refine(every);
  }
  return uniform.leaf_mesh();
}

class RefinementRun3d : public testing::TestWithParam<const char*> {};

TEST_P(RefinementRun3d, StaticIndentationRefinesTowardTheUniformlyRefinedSolution) {
  TempDir dir;
  const Mesh coarse = block(4, GetParam());
  const Mesh fine_mesh = uniformly_refined(coarse, 2);
  const RunReport fine = Simulation(indentation(dir, "fine"), fine_mesh, quiet()).run();
  const RunReport plain = Simulation(indentation(dir, "coarse"), coarse, quiet()).run();

  Scene scene = indentation(dir, "refined");
  scene.refinement = refine(0.3, 2);
  Simulation simulation(scene, coarse, quiet());
  const RunReport& refined = simulation.run();
  EXPECT_GT(refined.cells, coarse.cell_count());
  // Transition cells are many in 3D (a cone per face piece): count nodes, the unknowns.
  EXPECT_LT(simulation.mesh().node_count(), fine_mesh.node_count())
      << refined.cells << " cells against " << fine_mesh.cell_count();
  EXPECT_EQ(static_cast<int>(refined.state.displacement.size()), 3 * simulation.mesh().node_count());
  ASSERT_GE(refined.refinement.size(), 2u);
  EXPECT_EQ(refined.refinement.back().leaves_per_level.size(), 3u);  // levels 0, 1 and 2
  EXPECT_TRUE(refined.statistics.warnings.empty());

  const double coarse_error = error_at(plain.state.displacement, fine.state.displacement, coarse.node_count());
  const double refined_error = error_at(refined.state.displacement, fine.state.displacement, coarse.node_count());
  EXPECT_LT(refined_error, 0.5 * coarse_error) << "coarse " << coarse_error << ", refined " << refined_error;
  std::printf("%s: %d cells, %d nodes (uniform %d, %d); error %.3g (coarse %.3g)\n", GetParam(), refined.cells,
              simulation.mesh().node_count(), fine_mesh.cell_count(), fine_mesh.node_count(), refined_error,
              coarse_error);
  for (const std::string name : {"frame_000001.vtu", "final.vtu"})
    expect_conforming_block(read_mesh((dir.path() / "refined" / name).string()), name);
}

TEST_P(RefinementRun3d, DynamicProbeRefinesThenCoarsensBack) {
  TempDir dir;
  const Mesh coarse = block(4, GetParam());
  Scene scene = indentation(dir, "dynamic");
  // The probe goes 4 mm in and comes back out (a sinusoid over 0.4 s), then
  // the block rests: 0.8 s in 20 implicit steps.
  scene.model.prescribed[0].profile.kind = ProfileKind::sinusoid;
  scene.model.prescribed[0].profile.period = 0.8;
  scene.model.prescribed[0].profile.phase = 0;
  scene.solver.type = SolverType::implicit_euler;
  scene.solver.dt = 0.04;
  scene.solver.steps = 20;
  scene.solver.damping_mass = 20.0;
  scene.output.every = 5;
  scene.refinement = refine(0.3, 1);
  scene.refinement.every = 1;
  scene.refinement.calm_steps = 2;
  Simulation simulation(scene, coarse, quiet());
  const RunReport& report = simulation.run();
  EXPECT_TRUE(simulation.finished());
  int most = 0;
  for (const RefinementRecord& event : report.refinement) most = std::max(most, event.cells);
  ASSERT_GE(report.refinement.size(), 3u);
  EXPECT_GT(most, coarse.cell_count());
  EXPECT_EQ(report.refinement.back().cells, coarse.cell_count());  // back to the original cells
  for (const std::string name : {"frame_000005.vtu", "frame_000010.vtu", "final.vtu"})
    expect_conforming_block(read_mesh((dir.path() / "dynamic" / name).string()), name);
}

TEST_P(RefinementRun3d, LawSwitchingFollowsTheRefinedCells) {
  TempDir dir;
  const Mesh coarse = block(4, GetParam());
  Scene scene = indentation(dir, "switching");
  scene.solver.type = SolverType::implicit_euler;
  scene.solver.dt = 0.05;
  scene.solver.steps = 6;
  scene.model.prescribed[0].profile.duration = 0.3;
  scene.adaptivity.enabled = true;
  scene.adaptivity.ladder = {"hooke", "neohookean"};
  CriterionSpec criterion;
  criterion.name = "R_NL";
  criterion.threshold = 0.01;
  scene.adaptivity.criteria = {criterion};
  scene.refinement = refine(0.3, 1);
  Simulation simulation(scene, coarse, quiet());
  const RunReport& report = simulation.run();
  EXPECT_TRUE(simulation.finished());
  EXPECT_GT(report.cells, coarse.cell_count());
  int rich = 0;
  for (int cell = 0; cell < simulation.model().cell_count(); ++cell)
    rich += std::string(simulation.model().kernel(cell).law) == "neohookean";
  EXPECT_GT(rich, 0) << "cells under the probe climbed to neo-Hookean";
  EXPECT_LT(rich, simulation.model().cell_count());
  expect_conforming_block(read_mesh((dir.path() / "switching" / "final.vtu").string()), "final.vtu");
}

INSTANTIATE_TEST_SUITE_P(Blocks, RefinementRun3d, testing::Values("hex8", "tet6"));

}  // namespace
}  // namespace tensormass
