#include "simulation/summary_json.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <ostream>

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

using Json = nlohmann::ordered_json;

/// A number, or null where it is not finite (JSON has no NaN or infinity).
Json number(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

Json numbers(const std::vector<double>& values) {
  Json list = Json::array();
  for (double x : values) list.push_back(number(x));
  return list;
}

/// {"name": count, ...} in the given order.
Json counts(const std::vector<std::pair<std::string, int>>& named) {
  Json object = Json::object();
  for (const auto& [name, count] : named) object[name] = count;
  return object;
}

Json solver(const Scene& scene, const RunReport& report) {
  Json j{{"type", solver_type_name(scene.solver.type)}, {"linear", report.linear_solver}};
  if (scene.solver.is_dynamic()) {
    j["dt"] = number(scene.solver.dt);
    j["newton_iterations"] = scene.solver.newton_iterations;
    j["predictor"] = step_predictor_name(scene.solver.predictor);
  } else {
    j["load_steps"] = scene.solver.load_steps;
    j["tolerance"] = number(scene.solver.tolerance);
  }
  const char* wait_policy = std::getenv("OMP_WAIT_POLICY");
  const char* spin_count = std::getenv("GOMP_SPINCOUNT");
  j["project_hessian"] = scene.solver.project_hessian;
  j["threads"] = omp_get_max_threads();
  j["omp_wait_policy"] = wait_policy ? wait_policy : "unset";
  j["gomp_spincount"] = spin_count ? spin_count : "unset";
  return j;
}

Json memory_by_phase(const RunReport& report) {
  Json j = Json::object();
  for (const auto& [phase, per_rank] : report.peak_memory_mib_by_phase) j[phase] = numbers(per_rank);
  return j;
}

Json timings(const RunReport& report) {
  const SolveStatistics& s = report.statistics;
  const double other = std::max(0.0, report.wall_seconds - s.assembly_seconds - s.solve_seconds -
                                         report.output_seconds - report.criteria_seconds);
  return {{"criteria", number(report.criteria_seconds)},
          {"assembly", number(s.assembly_seconds)},
          {"solve", number(s.solve_seconds)},
          {"output", number(report.output_seconds)},
          {"other", number(other)},
          {"total", number(report.wall_seconds)}};
}

Json record_json(const AdaptivityRecord& r) {
  return {{"step", r.step},
          {"upgrades", r.upgrades},
          {"downgrades", r.downgrades},
          {"elements_per_law", counts(r.cells_per_law)}};
}

Json adaptivity(const Scene& scene, const RunReport& report) {
  Json criteria = Json::array();
  for (std::size_t i = 0; i < scene.adaptivity.criteria.size(); ++i)
    criteria.push_back({{"name", scene.adaptivity.criteria[i].name},
                        {"threshold", number(scene.adaptivity.criteria[i].threshold)},
                        {"seconds", number(i < report.criterion_seconds.size() ? report.criterion_seconds[i] : 0.0)}});
  Json per_step = Json::array();
  for (const AdaptivityRecord& r : report.adaptivity.listed) per_step.push_back(record_json(r));
  return {{"criteria", criteria},
          {"evaluations", report.adaptivity.evaluations},
          {"switching_evaluations", report.adaptivity.switching_evaluations},
          {"records", kAdaptivityRecordsFile},
          {"per_step", per_step}};
}

Json refinement(const RefinementSettings& settings, const RunReport& report) {
  Json events = Json::array();
  for (const RefinementRecord& event : report.refinement)
    events.push_back({{"step", event.step}, {"cells", event.cells}, {"leaves_per_level", event.leaves_per_level}});
  return {{"criterion", "R_ZZ"},
          {"threshold", number(settings.threshold)},
          {"max_level", settings.max_level},
          {"events", events}};
}

Json run_summary(const Scene& scene, const Model& model, const RunReport& report, const std::string& failure) {
  const SolveStatistics& s = report.statistics;
  const double mean = s.step_ms.mean(), median = s.step_ms.median();
  const bool dynamic = scene.solver.is_dynamic();
  Json j;
  j["status"] = failure.empty() ? "ok" : "failed";
  if (!failure.empty()) j["error"] = failure;
  j["version"] = kVersion;
  j["scene"] = scene.path;
  j["mesh"] = scene.mesh;
  j["solver"] = solver(scene, report);
  j["nodes"] = report.nodes;
  j["elements"] = report.cells;
  j["dofs"] = report.dofs;
  j["free_dofs"] = report.free_dofs;
  j["mpi_ranks"] = report.mpi_ranks;
  j["peak_memory_mib_per_rank"] = numbers(report.peak_memory_mib);
  Json cells_per_rank = Json::array();
  for (double cells : report.cells_per_rank) cells_per_rank.push_back(static_cast<long>(cells));
  j["cells_per_rank"] = cells_per_rank;
  j["peak_memory_mib_by_phase"] = memory_by_phase(report);
  j["steps"] = s.step_ms.size();
  if (report.resumed_from_step >= 0) j["resumed_from_step"] = report.resumed_from_step;
  j["time_per_step_ms"] = {{"mean", number(mean)}, {"median", number(median)}};
  j["time_per_phase_s"] = timings(report);
  j["newton_iterations"] = {{"total", s.newton_iterations},
                            {"per_step", s.newton_per_step.listed()},
                            {"shortened_by_line_search", s.shortened_steps}};
  // The first StepSeries::kListed steps; the means and medians cover all.
  j["per_step_ms"] = {{"listed_steps", s.step_ms.listed().size()},
                      {"total", numbers(s.step_ms.listed())},
                      {"assembly", numbers(report.step_assembly_ms.listed())},
                      {"solve", numbers(report.step_solve_ms.listed())},
                      {"criteria", numbers(report.step_criteria_ms.listed())}};
  j["linear_iterations"] = s.linear_iterations;
  j["factorizations"] = s.factorizations;
  j["elements_per_law"] = counts(report.cells_per_law);
  j["elements_per_type"] = counts(report.cells_per_type);
  j["switches"] = report.switches;
  if (scene.adaptivity.enabled) j["adaptivity"] = adaptivity(scene, report);
  if (scene.refinement.enabled) j["refinement"] = refinement(scene.refinement, report);
  Json law_ids = Json::object();
  for (std::size_t i = 0; i < model.law_names().size(); ++i) law_ids[std::to_string(i)] = model.law_names()[i];
  j["law_ids"] = law_ids;
  // Real time (RunReport::loop_seconds says what is timed); null for static solves.
  j["simulated_seconds"] = dynamic ? number(report.simulated_seconds) : Json(nullptr);
  j["time_loop_seconds"] = dynamic ? number(report.loop_seconds) : Json(nullptr);
  j["real_time_factor"] = dynamic ? number(report.real_time_factor()) : Json(nullptr);
  if (scene.solver.type == SolverType::explicit_euler) j["stable_dt_s"] = number(s.stable_dt);
  j["max_displacement"] = {{"value", number(report.max_displacement)}, {"node", report.max_displacement_node}};
  j["warnings"] = s.warnings;
  Json tracks = Json::object();
  for (const auto& [group, file] : report.tracks) tracks[group] = file;
  j["tracks"] = tracks;
  j["files"] = report.files;
  return j;
}

}  // namespace

void write_summary(const std::string& path, const Scene& scene, const Model& model, const RunReport& report,
                   const std::string& failure) {
  // Invalid UTF-8 in a name (a path, a group) is replaced, not thrown on.
  const std::string text =
      run_summary(scene, model, report, failure).dump(2, ' ', false, Json::error_handler_t::replace);
  io::write_atomically(path, [&](std::ostream& out) { out << text << '\n'; });
}

std::string adaptivity_record_line(const AdaptivityRecord& record) {
  return record_json(record).dump(-1, ' ', false, Json::error_handler_t::replace) + "\n";
}

}  // namespace tensormass::detail
