// The 3D tool indentation of `tensormass bench refine`: see
// refine_indentation.hpp and docs/results/refine.md.
#include "refine_indentation.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "tensormass/common/errors.hpp"
#include "tensormass/meshing/beam.hpp"
#include "tensormass/scene/scene.hpp"
#include "tensormass/simulation/simulation.hpp"

namespace tensormass::bench {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kErrorTarget = 0.02;  // error against the uniform max_level mesh ...
constexpr double kCostTarget = 0.3;    // ... at at most this fraction of its time per step
constexpr double kEventTarget = 1.0;   // a refinement event: at most one step of the refined mesh
constexpr double kCell = 0.01;         // the coarse cells' edge (m)

/// The sizes of a full or a quick run.
struct Setup {
  std::array<int, 3> coarse{10, 5, 10};
  int max_level = 2;
  int steps = 50;
  double duration = 0.5;  // the probe's ramp (s)
  double depth = 0.015;   // how far the probe goes down (m)
};

/// One run: the mesh (the coarse one refined uniformly `level` times), the
/// law, and the adaptivity on it.
struct RunSpec {
  std::string label;
  std::string law = "hooke";
  int level = 0;
  double zz = -1;  // R_ZZ threshold: refinement on when >= 0
  int every = 1;
  double nl = -1;           // R_NL threshold: law switching [hooke, neohookean] on when >= 0
  bool neo_family = false;  // compared with the neo-Hookean reference (else Hooke's)
  bool coarsen = true;
  int same_as = -1;  // the run of this index gives its figures (the same run, compared with another reference)
};

struct StepRecord {
  double wall_ms = 0;        // Simulation::step, output excluded
  double integrator_ms = 0;  // its integrator step (assembly, solves)
  bool event = false;        // the mesh changed after this step
};

struct Run {
  RunSpec spec;
  std::string failure;
  bool numerical = false;  // the failure is a NumericalError (else an input refused or a bug)
  std::vector<StepRecord> steps;
  double mean_ms = 0;  // per step
  int cells = 0, nodes = 0, peak_cells = 0, events = 0, factorizations = 0;
  std::vector<int> leaves_per_level;
  std::vector<std::pair<std::string, int>> cells_per_law;
  double event_ms_max = 0, event_ms_mean = 0, event_ratio_max = 0;  // ratio: event / step of the refined mesh
  double event_change_ms = 0, event_refactor_ms = 0;                // the largest event's two parts (see event_costs)
  double error = 0, largest = 0;
  std::vector<double> coarse_displacement;  // at the coarse mesh's nodes, final time (3 per node)
  double reference_ms = 0;                  // the mean_ms of the run it is compared with
};

Mesh block_mesh(const Setup& setup, int level) {
  BeamSpec spec;
  spec.dim = 3;
  const int factor = 1 << level;
  spec.cells = {setup.coarse[0] * factor, setup.coarse[1] * factor, setup.coarse[2] * factor};
  spec.size = {kCell * setup.coarse[0], kCell * setup.coarse[1], kCell * setup.coarse[2]};
  spec.phases = {{"hex8", 1.0}};
  Mesh mesh = make_beam(spec);
  const double eps = 1e-9, top = spec.size[1], mid_x = spec.size[0] / 2, mid_z = spec.size[2] / 2;
  mesh.add_node_group("base", [&](double, double y, double) { return y < eps; });
  mesh.add_node_group("probe", [&](double x, double y, double z) {
    return y > top - eps && std::abs(x - mid_x) <= 0.01 + eps && std::abs(z - mid_z) <= 0.01 + eps;
  });
  return mesh;
}

Scene block_scene(const Setup& setup, const RunSpec& spec, const std::string& directory) {
  Scene scene;
  scene.path = directory + "/indentation.yaml";
  scene.mesh = "indentation-hex8";
  MaterialSpec material;
  material.law = spec.law;
  material.constants = elastic_constants(5e3, 0.45);
  material.density = 1000;
  scene.model.materials = {material};
  scene.model.fixed = {"base"};
  PrescribedSpec probe;
  probe.region = "probe";
  probe.displacement = {0.0, -setup.depth, 0.0};
  probe.profile.kind = ProfileKind::ramp;
  probe.profile.duration = setup.duration;
  scene.model.prescribed = {probe};
  scene.solver.type = SolverType::implicit_euler;
  scene.solver.dt = 0.01;
  scene.solver.steps = setup.steps;
  if (spec.zz >= 0) {
    scene.refinement.enabled = true;
    scene.refinement.threshold = spec.zz;
    scene.refinement.max_level = setup.max_level;
    scene.refinement.every = spec.every;
    scene.refinement.coarsen = spec.coarsen;
  }
  if (spec.nl >= 0) {
    scene.adaptivity.enabled = true;
    scene.adaptivity.criteria = {{"R_NL", spec.nl, 0, ""}};
    scene.adaptivity.ladder = {"hooke", "neohookean"};
  }
  scene.output.directory = directory;
  return scene;
}

/// The node at each coarse grid point of `mesh` (keyed by its indices on the
/// coarse grid); nodes off the coarse grid are left out.
std::unordered_map<std::uint64_t, int> coarse_grid_nodes(const Mesh& mesh) {
  std::unordered_map<std::uint64_t, int> nodes;
  for (int node = 0; node < mesh.node_count(); ++node) {
    std::uint64_t key = 0;
    bool on_grid = true;
    for (int k = 0; k < 3; ++k) {
      const double x = mesh.rest_positions[3 * static_cast<std::size_t>(node) + k] / kCell;
      const double index = std::round(x);
      on_grid = on_grid && std::abs(x - index) < 1e-6;
      key = key * 4096 + static_cast<std::uint64_t>(index);
    }
    if (on_grid) nodes.emplace(key, node);
  }
  return nodes;
}

/// The final displacement of `mesh`'s nodes that sit at `coarse`'s nodes (3 per coarse node).
std::vector<double> at_coarse_nodes(const Mesh& coarse, const Mesh& mesh, const std::vector<double>& u) {
  const std::unordered_map<std::uint64_t, int> coarse_index = coarse_grid_nodes(coarse);
  const std::unordered_map<std::uint64_t, int> fine_index = coarse_grid_nodes(mesh);
  std::vector<double> picked(3 * static_cast<std::size_t>(coarse.node_count()), 0.0);
  for (const auto& [key, node] : coarse_index) {
    const auto found = fine_index.find(key);
    if (found == fine_index.end())
      throw std::runtime_error("indentation: a coarse node has no node at its place in the refined mesh");
    for (int k = 0; k < 3; ++k)
      picked[3 * static_cast<std::size_t>(node) + k] = u[3 * static_cast<std::size_t>(found->second) + k];
  }
  return picked;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const std::size_t middle = values.size() / 2;
  return values.size() % 2 ? values[middle] : (values[middle - 1] + values[middle]) / 2;
}

/// Event costs: the event step's wall time minus its integrator step, plus
/// what the first step on the new mesh costs over that mesh's median step
/// (its new symbolic analysis and factorisation). "A step of the refined
/// mesh": the median integrator step on the mesh the event made.
void event_costs(Run& run) {
  const std::vector<StepRecord>& steps = run.steps;
  double sum = 0;
  for (std::size_t s = 0; s < steps.size(); ++s) {
    if (!steps[s].event) continue;
    std::vector<double> segment;  // integrator steps on the mesh this event made
    std::size_t end = s + 1;
    for (; end < steps.size(); ++end) {
      segment.push_back(steps[end].integrator_ms);
      if (steps[end].event) break;
    }
    const double refined_step = segment.empty() ? steps[s].integrator_ms : median(segment);
    const double change = std::max(0.0, steps[s].wall_ms - steps[s].integrator_ms);
    const double refactor = s + 1 < steps.size() ? std::max(0.0, steps[s + 1].integrator_ms - refined_step) : 0.0;
    const double cost = change + refactor;
    sum += cost;
    if (cost > run.event_ms_max)
      run.event_ms_max = cost, run.event_change_ms = change, run.event_refactor_ms = refactor;
    if (refined_step > 0) run.event_ratio_max = std::max(run.event_ratio_max, cost / refined_step);
  }
  run.event_ms_mean = run.events ? sum / run.events : 0.0;
}

Run simulate(const Setup& setup, const RunSpec& spec, const Mesh& coarse, const std::string& directory) {
  Run run;
  run.spec = spec;
  const Mesh mesh = spec.level == 0 ? coarse : block_mesh(setup, spec.level);
  std::filesystem::create_directories(directory);
  try {
    Simulation simulation(block_scene(setup, spec, directory), mesh, RunOptions{false, false});
    run.peak_cells = simulation.mesh().cell_count();
    std::size_t events = simulation.report().refinement.size();
    double output = simulation.report().output_seconds;
    while (!simulation.finished()) {
      const auto start = Clock::now();
      simulation.step();
      const double wall = std::chrono::duration<double>(Clock::now() - start).count();
      const RunReport& report = simulation.report();
      StepRecord record;
      record.wall_ms = 1e3 * (wall - (report.output_seconds - output));
      output = report.output_seconds;
      record.integrator_ms = report.statistics.step_ms.empty() ? 0.0 : report.statistics.step_ms.back();
      record.event = report.refinement.size() > events;
      events = report.refinement.size();
      run.events += record.event ? 1 : 0;
      run.steps.push_back(record);
      run.peak_cells = std::max(run.peak_cells, simulation.mesh().cell_count());
    }
    const RunReport& report = simulation.report();
    run.cells = report.cells;
    run.nodes = report.nodes;
    run.factorizations = report.statistics.factorizations;
    run.cells_per_law = report.cells_per_law;
    run.leaves_per_level = report.refinement.empty() ? std::vector<int>{} : report.refinement.back().leaves_per_level;
    if (run.leaves_per_level.empty()) {
      run.leaves_per_level.assign(static_cast<std::size_t>(spec.level + 1), 0);
      run.leaves_per_level.back() = report.cells;
    }
    const std::vector<double>& u = report.state.displacement;
    for (std::size_t node = 0; 3 * node < u.size(); ++node)
      run.largest = std::max(run.largest, std::hypot(u[3 * node], u[3 * node + 1], u[3 * node + 2]));
    run.coarse_displacement = at_coarse_nodes(coarse, simulation.mesh(), u);
  } catch (const NumericalError& failure) {
    run.failure = std::string("failed: ") + failure.what();
    run.numerical = true;
  } catch (const InputError& refused) {
    run.failure = std::string("not run: ") + refused.what();
  } catch (const std::exception& error) {
    run.failure = std::string("failed: ") + error.what();
  }
  double total = 0;
  for (const StepRecord& step : run.steps) total += step.wall_ms;
  run.mean_ms = run.steps.empty() ? 0.0 : total / static_cast<double>(run.steps.size());
  event_costs(run);
  std::error_code ignored;
  std::filesystem::remove_all(directory, ignored);
  return run;
}

/// Largest difference at the coarse nodes over the reference's largest displacement.
double error_against(const Run& run, const Run& reference) {
  double worst = 0;
  const std::vector<double>& a = run.coarse_displacement;
  const std::vector<double>& b = reference.coarse_displacement;
  for (std::size_t node = 0; 3 * node < a.size(); ++node)
    worst = std::max(worst, std::hypot(a[3 * node] - b[3 * node], a[3 * node + 1] - b[3 * node + 1],
                                       a[3 * node + 2] - b[3 * node + 2]));
  return worst / std::max(reference.largest, 1e-300);
}

std::string list_text(const std::vector<int>& values, const char* separator) {
  std::string text;
  for (std::size_t i = 0; i < values.size(); ++i) text += (i ? separator : "") + std::to_string(values[i]);
  return text;
}

std::string laws_text(const std::vector<std::pair<std::string, int>>& cells) {
  std::string text;
  for (const auto& [law, count] : cells) text += (text.empty() ? "" : ", ") + std::to_string(count) + " " + law;
  return text;
}

void print_header() {
  std::printf("%-32s %6s %6s %-16s %6s %6s %9s %6s %13s %7s %7s %8s %7s  %s\n", "run", "nodes", "cells",
              "leaves per level", "peak", "events", "ms/step", "x ref", "event ms", "ev/step", "ev/ref", "error %",
              "factor.", "cells per law (end)");
}

void print_run(const Run& run) {
  if (!run.failure.empty() && run.steps.empty()) {
    std::printf("%-32s %s\n", run.spec.label.c_str(), run.failure.c_str());
    return;
  }
  char event[48] = "", ratio[32] = "", to_reference[32] = "";
  if (run.events) {
    std::snprintf(event, sizeof event, "%.0f+%.0f", run.event_change_ms, run.event_refactor_ms);
    std::snprintf(ratio, sizeof ratio, "%.2f", run.event_ratio_max);
    std::snprintf(to_reference, sizeof to_reference, "%.2f", run.event_ms_max / run.reference_ms);
  }
  std::printf("%-32s %6d %6d %-16s %6d %6d %9.1f %6.3f %13s %7s %7s %8.3f %7d  %s\n", run.spec.label.c_str(), run.nodes,
              run.cells, list_text(run.leaves_per_level, "/").c_str(), run.peak_cells, run.events, run.mean_ms,
              run.mean_ms / run.reference_ms, event, ratio, to_reference, 100 * run.error, run.factorizations,
              laws_text(run.cells_per_law).c_str());
  if (!run.failure.empty()) std::printf("%-32s %s\n", "", run.failure.c_str());
}

// --json: figures with six significant digits, as always written.

Json json_of(const RunSpec& spec) {
  const bool refines = spec.zz >= 0;
  return {{"label", spec.label},
          {"law", spec.law},
          {"uniform_level", spec.level},
          {"reference", spec.neo_family ? "neohookean" : "hooke"},
          {"refine_threshold", refines ? number(spec.zz, 6) : Json(nullptr)},
          {"every", refines ? Json(spec.every) : Json(nullptr)},
          {"switch_threshold", spec.nl >= 0 ? number(spec.nl, 6) : Json(nullptr)}};
}

/// The run's failure on one line, or null.
Json failure_json(const std::string& failure) {
  if (failure.empty()) return nullptr;
  std::string line = failure;
  std::replace(line.begin(), line.end(), '\n', ' ');
  return line;
}

Json json_of(const Run& r) {
  const auto per_reference = [&](double ms) { return r.reference_ms > 0 ? ms / r.reference_ms : 0.0; };
  Json cells_per_law = Json::object();
  for (const auto& [law, count] : r.cells_per_law) cells_per_law[law] = count;
  Json j = json_of(r.spec);
  j["completed_steps"] = r.steps.size();
  j["cells"] = r.cells;
  j["nodes"] = r.nodes;
  j["leaves_per_level"] = r.leaves_per_level;
  j["peak_cells"] = r.peak_cells;
  j["events"] = r.events;
  j["ms_per_step"] = number(r.mean_ms, 6);
  j["ms_ratio_to_reference"] = number(per_reference(r.mean_ms), 6);
  j["event_ms_max"] = number(r.event_ms_max, 6);
  j["event_ms_mean"] = number(r.event_ms_mean, 6);
  j["event_change_ms"] = number(r.event_change_ms, 6);
  j["event_refactor_ms"] = number(r.event_refactor_ms, 6);
  j["event_to_refined_step_max"] = number(r.event_ratio_max, 6);
  j["event_to_reference_step_max"] = number(per_reference(r.event_ms_max), 6);
  j["error"] = number(r.error, 6);
  j["factorizations"] = r.factorizations;
  j["cells_per_law"] = cells_per_law;
  j["failure"] = failure_json(r.failure);
  return j;
}

Json json_of(const Setup& setup, int coarse_cells, const std::vector<Run>& runs) {
  Json list = Json::array();
  for (const Run& run : runs) list.push_back(json_of(run));
  return {{"coarse_cells", coarse_cells},
          {"max_level", setup.max_level},
          {"steps", setup.steps},
          {"probe_depth", number(setup.depth, 6)},
          {"error_target", number(kErrorTarget, 6)},
          {"cost_target", number(kCostTarget, 6)},
          {"event_target", number(kEventTarget, 6)},
          {"runs", list}};
}

RunSpec refined(const std::string& law, double zz, int every, double nl, bool neo_family, bool coarsen = true) {
  RunSpec spec;
  spec.law = law;
  spec.zz = zz;
  spec.every = every;
  spec.nl = nl;
  spec.neo_family = neo_family;
  spec.coarsen = coarsen;
  char label[96];
  const char* coarsening = coarsen ? "" : " no coars.";
  if (zz >= 0 && nl >= 0) std::snprintf(label, sizeof label, "R_ZZ %.2f/%d%s + R_NL %g", zz, every, coarsening, nl);
  else if (zz >= 0) std::snprintf(label, sizeof label, "%s, R_ZZ %.2f/%d%s", law.c_str(), zz, every, coarsening);
  else std::snprintf(label, sizeof label, "switching R_NL %g (coarse)", nl);
  spec.label = label;
  return spec;
}

RunSpec uniform(const std::string& law, int level, bool neo_family) {
  RunSpec spec;
  spec.law = law;
  spec.level = level;
  spec.neo_family = neo_family;
  spec.label = law + (level == 0 ? ", coarse" : ", uniform level " + std::to_string(level));
  return spec;
}

}  // namespace

IndentationResult refine_indentation(bool quick) {
  Setup setup;
  if (quick) {
    setup.max_level = 1;
    setup.steps = 10;
    setup.duration = 0.1;
    setup.depth = 0.005;
  }
  const Mesh coarse = block_mesh(setup, 0);
  const int L = setup.max_level;
  std::printf(
      "\n## 3D tool indentation\n\n"
      "10 x 5 x 10 cm block of %d hex8 (1 cm), E 5 kPa, nu 0.45, base fixed, 2 x 2 cm probe %.1f cm down over\n"
      "%.1f s, implicit Euler dt 0.01, %d steps, max_level %d, coarsening on (hysteresis 0.5, 5 calm checks)\n"
      "unless said.\n"
      "Each run through Simulation, one after the other; ms/step: wall time of Simulation::step (final output\n"
      "excluded), every refinement event included; x ref: over the uniform level-%d mesh of the same law's.\n"
      "event ms: the largest event, A+B: A the step's wall time minus its integrator step (R_ZZ, the hierarchy's\n"
      "change, the state carried, model, assembler and solver built again), B what the first step on the new mesh\n"
      "costs over that mesh's median step (its new factorisation). ev/step: the largest event over the median\n"
      "step on the mesh it made; ev/ref: over the mean step of the uniform level-%d mesh (the same law's).\n"
      "error: largest displacement difference at the coarse mesh's %d nodes at the final time against the\n"
      "uniform level-%d mesh of the same law, over its largest displacement. nodes, cells: at the end (transition\n"
      "cells included); peak: the most cells during the run. R_ZZ t/N: refine at R_ZZ >= t x the run's largest\n"
      "every N steps; no coars.: coarsening off.\n\n",
      coarse.cell_count(), 100 * setup.depth, setup.duration, setup.steps, L, L, L, coarse.node_count(), L);
  std::vector<RunSpec> specs = {uniform("hooke", 0, false), uniform("hooke", L, false)};
  if (L > 1) specs.push_back(uniform("hooke", 1, false));
  const std::vector<std::pair<double, int>> hooke_refined =
      quick ? std::vector<std::pair<double, int>>{{0.3, 2}}
            : std::vector<std::pair<double, int>>{{0.1, 5}, {0.1, 10}, {0.2, 5}, {0.2, 10}, {0.3, 5}};
  for (const auto& [zz, every] : hooke_refined) specs.push_back(refined("hooke", zz, every, -1, false));
  if (!quick) specs.push_back(refined("hooke", 0.1, 5, -1, false, false));
  const std::size_t neo_start = specs.size();
  specs.push_back(uniform("neohookean", 0, true));
  specs.push_back(uniform("neohookean", L, true));
  specs.push_back(uniform("hooke", L, true));  // Hooke's own error against neo-Hookean: run 1 again
  specs.back().same_as = 1;
  specs.push_back(refined("hooke", -1, 1, 0.01, true));
  if (quick) {
    specs.push_back(refined("neohookean", 0.3, 2, -1, true));
    specs.push_back(refined("hooke", 0.3, 2, 0.01, true));
  } else {
    specs.push_back(refined("hooke", -1, 1, 0.03, true));
    specs.push_back(refined("neohookean", 0.1, 5, -1, true));
    specs.push_back(refined("hooke", 0.1, 5, 0.01, true));
    specs.push_back(refined("neohookean", 0.1, 5, -1, true, false));
    for (const double nl : {0.01, 0.03}) specs.push_back(refined("hooke", 0.1, 5, nl, true, false));
  }

  const std::string directory = (std::filesystem::temp_directory_path() /
                                 ("tensormass-bench-refine-" + std::to_string(static_cast<long>(getpid()))))
                                    .string();
  std::vector<Run> runs;
  IndentationResult result;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (specs[i].same_as >= 0) {
      runs.push_back(runs[static_cast<std::size_t>(specs[i].same_as)]);
      runs.back().spec = specs[i];
      continue;
    }
    std::fprintf(stderr, "bench refine: %s ...\n", specs[i].label.c_str());
    runs.push_back(simulate(setup, specs[i], coarse, directory + "/run-" + std::to_string(i)));
  }
  std::error_code ignored;
  std::filesystem::remove_all(directory, ignored);
  const Run& hooke_reference = runs[1];
  const Run& neo_reference = runs[neo_start + 1];
  for (std::size_t i = 0; i < runs.size(); ++i) {
    Run& run = runs[i];
    const bool uniform_run = run.spec.zz < 0 && run.spec.nl < 0;
    // A uniform run that fails, a refused scene, or in the quick smoke test any failure, fails the command.
    if (!run.failure.empty() && (uniform_run || !run.numerical || quick)) result.failed = true;
    const Run& reference = run.spec.neo_family ? neo_reference : hooke_reference;
    run.reference_ms = reference.mean_ms;
    if (run.failure.empty() && reference.failure.empty()) run.error = error_against(run, reference);
  }
  std::printf("Against Hooke on the uniform level-%d mesh:\n\n", L);
  print_header();
  for (std::size_t i = 0; i < neo_start; ++i) print_run(runs[i]);
  std::printf("\nAgainst neo-Hookean on the uniform level-%d mesh (law switching: ladder [hooke, neohookean]):\n\n", L);
  print_header();
  for (std::size_t i = neo_start; i < runs.size(); ++i) print_run(runs[i]);

  std::printf("\ntargets, 3D indentation%s:\n", quick ? " (quick: not the targets' sizes)" : "");
  std::printf("  within %.0f %% of the uniform level-%d mesh at <= %.1fx its time per step (Hooke):\n",
              100 * kErrorTarget, L, kCostTarget);
  for (std::size_t i = 0; i < neo_start; ++i) {
    const Run& run = runs[i];
    if (run.spec.zz < 0) continue;
    if (!run.failure.empty()) {
      std::printf("    %-32s -> NOT RUN (%s)\n", run.spec.label.c_str(), run.failure.c_str());
      continue;
    }
    const double ratio = run.mean_ms / run.reference_ms;
    std::printf("    %-32s error %.2f %%, %.2fx -> %s\n", run.spec.label.c_str(), 100 * run.error, ratio,
                run.error <= kErrorTarget && ratio <= kCostTarget ? "met" : "MISSED");
  }
  std::printf(
      "  refining or coarsening costs at most one step of the refined mesh (largest event over the median step on\n"
      "  the mesh it made; in brackets, over a step of the uniform level-%d mesh):\n",
      L);
  for (const Run& run : runs) {
    if (run.spec.zz < 0 || !run.failure.empty() || run.events == 0) continue;
    const double to_reference = run.event_ms_max / run.reference_ms;
    std::printf("    %-32s %d events, largest %.1f ms = %.2fx -> %s (%.2fx -> %s)\n", run.spec.label.c_str(),
                run.events, run.event_ms_max, run.event_ratio_max,
                run.event_ratio_max <= kEventTarget ? "met" : "MISSED", to_reference,
                to_reference <= kEventTarget ? "met" : "MISSED");
  }
  std::printf("  both kinds of adaptivity (against neo-Hookean level %d): error, time per step over its:\n", L);
  for (std::size_t i = neo_start; i < runs.size(); ++i) {
    const Run& run = runs[i];
    if (!run.failure.empty()) std::printf("    %-32s %s\n", run.spec.label.c_str(), run.failure.c_str());
    else
      std::printf("    %-32s %6.2f %%, %.3fx\n", run.spec.label.c_str(), 100 * run.error,
                  run.mean_ms / run.reference_ms);
  }
  result.json = json_of(setup, coarse.cell_count(), runs);
  return result;
}

}  // namespace tensormass::bench
