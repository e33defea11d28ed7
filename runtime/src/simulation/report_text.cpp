// The one-screen summary at the end of `tensormass run`.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "simulation/summary_json.hpp"
#include "tensormass/simulation/simulation.hpp"

namespace tensormass {

namespace {

std::string list(const std::vector<std::pair<std::string, int>>& items) {
  std::ostringstream text;
  for (std::size_t i = 0; i < items.size(); ++i) text << (i ? ", " : "") << items[i].second << " " << items[i].first;
  return text.str();
}

std::string format(const char* pattern, double a, double b = 0, double c = 0) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, pattern, a, b, c);
  return buffer;
}

}  // namespace

std::string format_report(const Scene& scene, const RunReport& report) {
  const SolveStatistics& s = report.statistics;
  const double mean = s.step_ms.mean(), median = s.step_ms.median();
  const bool dynamic = scene.solver.is_dynamic();
  std::ostringstream text;
  text << "tensormass run " << scene.path << "\n";
  text << "  mesh      " << scene.mesh << ": " << list(report.cells_per_type) << "; " << report.nodes << " nodes, "
       << report.dofs << " dofs (" << report.free_dofs << " free)\n";
  text << "  laws      " << list(report.cells_per_law) << "\n";
  text << "  solver    " << solver_type_name(scene.solver.type);
  if (dynamic) text << format(", dt %g s, %g steps", scene.solver.dt, scene.solver.steps);
  else text << format(", %g load steps, tolerance %g", scene.solver.load_steps, scene.solver.tolerance);
  text << ", linear: " << report.linear_solver;
  if (report.mpi_ranks > 1) text << " on " << report.mpi_ranks << " MPI ranks";
  text << "\n";
  if (scene.solver.type == SolverType::explicit_euler) text << format("  stable dt %.4g s (estimated)\n", s.stable_dt);
  text << format("  time      %.3f s; per step mean %.4g ms, median %.4g ms\n", report.wall_seconds, mean, median);
  text << format("  phases    assembly %.3f s, solve %.3f s", s.assembly_seconds, s.solve_seconds)
       << format(", criteria %.3f s, output %.3f s\n", report.criteria_seconds, report.output_seconds);
  if (scene.solver.type != SolverType::explicit_euler) {
    text << "  newton    " << s.newton_iterations << " iterations";
    if (!s.newton_per_step.empty())
      text << format(" (%.2f per step)", static_cast<double>(s.newton_iterations) / s.newton_per_step.size());
    if (s.shortened_steps > 0) text << ", " << s.shortened_steps << " shortened by the line search";
    text << "; linear iterations " << s.linear_iterations;
    if (s.factorizations > 0) text << ", factorisations " << s.factorizations;
    text << "\n";
  }
  if (scene.adaptivity.enabled) {
    text << "  adapt     ";
    for (std::size_t i = 0; i < scene.adaptivity.criteria.size(); ++i)
      text << (i ? ", " : "") << scene.adaptivity.criteria[i].name << " " << scene.adaptivity.criteria[i].threshold;
    text << ": " << report.switches << " switches" << format(", criteria %.3f s\n", report.criteria_seconds);
    // The first checks that switched something (every check is in adaptivity.jsonl).
    std::ostringstream steps;
    const std::vector<AdaptivityRecord>& switching = report.adaptivity.switching;
    const std::size_t shown = std::min<std::size_t>(switching.size(), 6);
    for (std::size_t i = 0; i < shown; ++i) {
      steps << (i ? ", " : "") << "step " << switching[i].step << " +" << switching[i].upgrades;
      if (switching[i].downgrades) steps << " -" << switching[i].downgrades;
    }
    const long hidden = report.adaptivity.switching_evaluations - static_cast<long>(shown);
    if (shown)
      text << "  switched  " << steps.str() << (hidden > 0 ? " and " + std::to_string(hidden) + " more" : "") << "\n";
  }
  if (dynamic)
    text << format("  speed     real-time factor %.3g (%.4g s simulated in %.4g s)\n", report.real_time_factor(),
                   report.simulated_seconds, report.loop_seconds);
  text << format("  result    max displacement %.6g", report.max_displacement) << " at node "
       << report.max_displacement_node << "\n";
  for (const std::string& warning : s.warnings) text << "  warning   " << warning << "\n";
  text << "  output    " << report.output_directory << "/ :";
  for (const std::string& file : report.files) text << " " << file;
  text << "\n";
  return text.str();
}

}  // namespace tensormass
