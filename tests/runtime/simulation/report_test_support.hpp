/// \file report_test_support.hpp
/// The hand-made run of the summary.json and report-text tests: a 4-load-step
/// static solve of an 8-quad beam, its figures chosen to check by hand.
#ifndef TENSORMASS_TESTS_SIMULATION_REPORT_TEST_SUPPORT_HPP
#define TENSORMASS_TESTS_SIMULATION_REPORT_TEST_SUPPORT_HPP

#include "support/cantilever.hpp"
#include "tensormass/simulation/simulation.hpp"

namespace tensormass::test {

/// test::cantilever("stvk") named scenes/beam.yaml on meshes/beam.msh, 4 load steps.
inline Scene report_scene() {
  Scene scene = cantilever("stvk");
  scene.path = "scenes/beam.yaml";
  scene.mesh = "meshes/beam.msh";
  scene.solver.load_steps = 4;
  scene.solver.tolerance = 1e-8;
  return scene;
}

/// The run's report: step times 4, 1, 3, 10 ms (mean 4.5, median 3.5),
/// 9 Newton iterations (3, 2, 2, 2), 8 quad4 cells (6 stvk, 2 hooke).
inline RunReport report_of_four_steps() {
  RunReport report;
  report.output_directory = "out";
  report.nodes = 15;
  report.cells = 8;
  report.dofs = 30;
  report.free_dofs = 24;
  report.linear_solver = "cholmod";
  report.statistics.step_ms = {4.0, 1.0, 3.0, 10.0};
  report.statistics.newton_iterations = 9;
  report.statistics.newton_per_step = {3, 2, 2, 2};
  report.statistics.linear_iterations = 0;
  report.statistics.factorizations = 9;
  report.statistics.assembly_seconds = 0.25;
  report.statistics.solve_seconds = 0.5;
  report.output_seconds = 0.125;
  report.wall_seconds = 2.0;
  report.cells_per_law = {{"stvk", 6}, {"hooke", 2}};
  report.cells_per_type = {{"quad4", 8}};
  report.max_displacement = 0.75;
  report.max_displacement_node = 14;
  report.files = {"final.vtu", "series.pvd", "summary.json"};
  return report;
}

}  // namespace tensormass::test

#endif
