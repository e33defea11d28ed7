#include "simulation/summary_json.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <sstream>

#include "tensormass/common/version.hpp"
#include "tensormass/io/atomic_file.hpp"

namespace tensormass::detail {

std::pair<double, double> mean_and_median(std::vector<double> values) {
  if (values.empty()) return {0.0, 0.0};
  double mean = 0;
  for (double x : values) mean += x / values.size();
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  const double median = n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
  return {mean, median};
}

namespace {

std::string quoted(const std::string& text) {
  std::ostringstream out;
  out << '"';
  for (char c : text) {
    switch (c) {
      case '"': out << "\\\""; break;
      case '\\': out << "\\\\"; break;
      case '\n': out << "\\n"; break;
      case '\t': out << "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          out << "\\u" << std::hex << std::setw(4) << std::setfill('0') << int(c) << std::dec;
        else out << c;
    }
  }
  out << '"';
  return out.str();
}

std::string number(double x) {
  if (!std::isfinite(x)) return "null";
  std::ostringstream out;
  out << std::setprecision(17) << x;
  return out.str();
}

}  // namespace

void write_summary(const std::string& path, const Scene& scene, const Model& model, const RunReport& report,
                   const std::string& failure) {
  const SolveStatistics& s = report.statistics;
  const auto [mean, median] = mean_and_median(s.step_ms);
  const double other = std::max(0.0, report.wall_seconds - s.assembly_seconds - s.solve_seconds -
                                         report.output_seconds - report.criteria_seconds);
  const bool dynamic = scene.solver.is_dynamic();
  std::ostringstream j;
  j << "{\n";
  j << "  \"status\": " << quoted(failure.empty() ? "ok" : "failed") << ",\n";
  j << "  \"version\": " << quoted(kVersion) << ",\n";
  if (!failure.empty()) j << "  \"error\": " << quoted(failure) << ",\n";
  j << "  \"scene\": " << quoted(scene.path) << ",\n";
  j << "  \"mesh\": " << quoted(scene.mesh) << ",\n";
  j << "  \"solver\": {\"type\": " << quoted(std::string(solver_type_name(scene.solver.type)))
    << ", \"linear\": " << quoted(report.linear_solver);
  if (dynamic)
    j << ", \"dt\": " << number(scene.solver.dt) << ", \"newton_iterations\": " << scene.solver.newton_iterations
      << ", \"predictor\": " << quoted(std::string(step_predictor_name(scene.solver.predictor)));
  else j << ", \"load_steps\": " << scene.solver.load_steps << ", \"tolerance\": " << number(scene.solver.tolerance);
  const char* wait_policy = std::getenv("OMP_WAIT_POLICY");
  const char* spin_count = std::getenv("GOMP_SPINCOUNT");
  j << ", \"project_hessian\": " << (scene.solver.project_hessian ? "true" : "false");
  j << ", \"threads\": " << omp_get_max_threads()
    << ", \"omp_wait_policy\": " << quoted(wait_policy ? wait_policy : "unset")
    << ", \"gomp_spincount\": " << quoted(spin_count ? spin_count : "unset") << "},\n";
  j << "  \"nodes\": " << report.nodes << ", \"elements\": " << report.cells << ", \"dofs\": " << report.dofs
    << ", \"free_dofs\": " << report.free_dofs << ", \"mpi_ranks\": " << report.mpi_ranks << ",\n";
  j << "  \"peak_memory_mib_per_rank\": [";
  for (std::size_t i = 0; i < report.peak_memory_mib.size(); ++i)
    j << (i ? ", " : "") << number(report.peak_memory_mib[i]);
  j << "],\n";
  j << "  \"cells_per_rank\": [";
  for (std::size_t i = 0; i < report.cells_per_rank.size(); ++i)
    j << (i ? ", " : "") << static_cast<long>(report.cells_per_rank[i]);
  j << "],\n";
  j << "  \"peak_memory_mib_by_phase\": {";
  for (std::size_t p = 0; p < report.peak_memory_mib_by_phase.size(); ++p) {
    const auto& [phase, per_rank] = report.peak_memory_mib_by_phase[p];
    j << (p ? ", " : "") << quoted(phase) << ": [";
    for (std::size_t i = 0; i < per_rank.size(); ++i) j << (i ? ", " : "") << number(per_rank[i]);
    j << "]";
  }
  j << "},\n";
  j << "  \"steps\": " << s.step_ms.size() << ",\n";
  if (report.resumed_from_step >= 0) j << "  \"resumed_from_step\": " << report.resumed_from_step << ",\n";
  j << "  \"time_per_step_ms\": {\"mean\": " << number(mean) << ", \"median\": " << number(median) << "},\n";
  j << "  \"time_per_phase_s\": {\"criteria\": " << number(report.criteria_seconds)
    << ", \"assembly\": " << number(s.assembly_seconds) << ", \"solve\": " << number(s.solve_seconds)
    << ", \"output\": " << number(report.output_seconds) << ", \"other\": " << number(other)
    << ", \"total\": " << number(report.wall_seconds) << "},\n";
  j << "  \"newton_iterations\": {\"total\": " << s.newton_iterations << ", \"per_step\": [";
  for (std::size_t i = 0; i < s.newton_per_step.size(); ++i) j << (i ? ", " : "") << s.newton_per_step[i];
  j << "], \"shortened_by_line_search\": " << s.shortened_steps << "},\n";
  auto series = [&](const char* name, const std::vector<double>& values) {
    j << "\"" << name << "\": [";
    for (std::size_t i = 0; i < values.size(); ++i) j << (i ? ", " : "") << number(values[i]);
    j << "]";
  };
  j << "  \"per_step_ms\": {";
  series("total", s.step_ms);
  j << ", ";
  series("assembly", report.step_assembly_ms);
  j << ", ";
  series("solve", report.step_solve_ms);
  j << ", ";
  series("criteria", report.step_criteria_ms);
  j << "},\n";
  j << "  \"linear_iterations\": " << s.linear_iterations << ",\n";
  j << "  \"factorizations\": " << s.factorizations << ",\n";
  j << "  \"elements_per_law\": {";
  for (std::size_t i = 0; i < report.cells_per_law.size(); ++i)
    j << (i ? ", " : "") << quoted(report.cells_per_law[i].first) << ": " << report.cells_per_law[i].second;
  j << "},\n  \"elements_per_type\": {";
  for (std::size_t i = 0; i < report.cells_per_type.size(); ++i)
    j << (i ? ", " : "") << quoted(report.cells_per_type[i].first) << ": " << report.cells_per_type[i].second;
  j << "},\n  \"switches\": " << report.switches << ",\n";
  if (scene.adaptivity.enabled) {
    j << "  \"adaptivity\": {\"criteria\": [";
    for (std::size_t i = 0; i < scene.adaptivity.criteria.size(); ++i)
      j << (i ? ", " : "") << "{\"name\": " << quoted(scene.adaptivity.criteria[i].name)
        << ", \"threshold\": " << number(scene.adaptivity.criteria[i].threshold)
        << ", \"seconds\": " << number(i < report.criterion_seconds.size() ? report.criterion_seconds[i] : 0.0) << "}";
    j << "], \"per_step\": [";
    for (std::size_t i = 0; i < report.adaptivity.size(); ++i) {
      const AdaptivityRecord& r = report.adaptivity[i];
      j << (i ? ",\n    " : "\n    ") << "{\"step\": " << r.step << ", \"upgrades\": " << r.upgrades
        << ", \"downgrades\": " << r.downgrades << ", \"elements_per_law\": {";
      for (std::size_t k = 0; k < r.cells_per_law.size(); ++k)
        j << (k ? ", " : "") << quoted(r.cells_per_law[k].first) << ": " << r.cells_per_law[k].second;
      j << "}}";
    }
    j << "]},\n";
  }
  if (scene.refinement.enabled) {
    const RefinementSettings& r = scene.refinement;
    j << "  \"refinement\": {\"criterion\": \"R_ZZ\", \"threshold\": " << number(r.threshold)
      << ", \"max_level\": " << r.max_level << ", \"events\": [";
    for (std::size_t i = 0; i < report.refinement.size(); ++i) {
      const RefinementRecord& event = report.refinement[i];
      j << (i ? ",\n    " : "\n    ") << "{\"step\": " << event.step << ", \"cells\": " << event.cells
        << ", \"leaves_per_level\": [";
      for (std::size_t level = 0; level < event.leaves_per_level.size(); ++level)
        j << (level ? ", " : "") << event.leaves_per_level[level];
      j << "]}";
    }
    j << "]},\n";
  }
  j << "  \"law_ids\": {";
  for (std::size_t i = 0; i < model.law_names().size(); ++i)
    j << (i ? ", " : "") << quoted(std::to_string(i)) << ": " << quoted(model.law_names()[i]);
  j << "},\n";
  // Real time (RunReport::loop_seconds says what is timed); null for static solves.
  j << "  \"simulated_seconds\": " << (dynamic ? number(report.simulated_seconds) : "null")
    << ", \"time_loop_seconds\": " << (dynamic ? number(report.loop_seconds) : "null")
    << ", \"real_time_factor\": " << (dynamic ? number(report.real_time_factor()) : "null") << ",\n";
  if (scene.solver.type == SolverType::explicit_euler) j << "  \"stable_dt_s\": " << number(s.stable_dt) << ",\n";
  j << "  \"max_displacement\": {\"value\": " << number(report.max_displacement)
    << ", \"node\": " << report.max_displacement_node << "},\n";
  j << "  \"warnings\": [";
  for (std::size_t i = 0; i < s.warnings.size(); ++i) j << (i ? ", " : "") << quoted(s.warnings[i]);
  j << "],\n  \"tracks\": {";
  for (std::size_t i = 0; i < report.tracks.size(); ++i)
    j << (i ? ", " : "") << quoted(report.tracks[i].first) << ": " << quoted(report.tracks[i].second);
  j << "},\n  \"files\": [";
  for (std::size_t i = 0; i < report.files.size(); ++i) j << (i ? ", " : "") << quoted(report.files[i]);
  j << "]\n}\n";
  const std::string text = j.str();
  io::write_atomically(path, [&](std::ostream& out) { out << text; });
}

}  // namespace tensormass::detail
