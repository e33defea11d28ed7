// `tensormass bench refine`: see refine_bench.hpp and docs/results/refine.md.
#include "refine_bench.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_metadata.hpp"
#include "machine_info.hpp"
#include "refine_indentation.hpp"
#include "tensormass/adaptivity/zz_indicator.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/integrators/integrators.hpp"
#include "tensormass/io/atomic_file.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/meshing/beam.hpp"
#include "tensormass/refinement/hierarchical_mesh.hpp"
#include "tensormass/scene/scene.hpp"

namespace tensormass::bench {

namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kUsage =
    "usage: tensormass bench refine [--quick] [--json FILE]\n"
    "  --quick        a coarser plate, a 3D block refined one level, fewer runs (CI smoke test, a few seconds)\n"
    "  --json FILE    also write the results as JSON to FILE (atomically)\n";

constexpr int kMaxLevel = 2;
constexpr double kErrorTarget = 0.4;  // adaptive error / coarse error
constexpr double kCellTarget = 0.5;   // adaptive cells / reference cells

struct Options {
  bool quick = false;
  std::string json;
};

/// The plate of refine_bench.hpp: `cells` quads across, half as many up.
Mesh plate_mesh(int cells) {
  BeamSpec spec;
  spec.dim = 2;
  spec.cells = {cells, cells / 2, 1};
  spec.size = {0.1, 0.05, 1.0};
  spec.phases = {{"quad4", 1.0}};
  Mesh mesh = make_beam(spec);
  const double eps = 1e-9;
  mesh.add_node_group("bottom", [&](double, double y, double) { return y < eps; });
  mesh.add_node_group("probe",
                      [&](double x, double y, double) { return y > 0.05 - eps && std::abs(x - 0.05) <= 0.01 + eps; });
  return mesh;
}

/// Static Hooke, bottom fixed, the probe's nodes moved 5 mm down.
Scene plate_scene() {
  Scene scene;
  scene.path = "bench-refine-plate.yaml";
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
  return scene;
}

struct Solution {
  std::vector<double> displacement;
  double seconds = 0;  // model, assembler, solver and the solve
};

/// A static solve of the plate scene on `mesh`, with default settings.
Solution solve(const Mesh& mesh, const Scene& scene) {
  const auto start = Clock::now();
  const Model model(mesh, scene.model);
  const Assembler assembler(model);
  auto linear = make_linear_solver(scene.solver.linear);
  SolveStatistics statistics;
  Integration run{model, assembler, *linear, scene.solver, statistics};
  State state;
  solve_static(run, state, nullptr);
  return {state.displacement, std::chrono::duration<double>(Clock::now() - start).count()};
}

/// Largest distance at the first `nodes` nodes (the coarse mesh's: the
/// hierarchy keeps them first) over the reference's largest displacement.
double coarse_node_error(const std::vector<double>& u, const std::vector<double>& reference, int nodes) {
  double worst = 0, largest = 0;
  for (int node = 0; node < nodes; ++node) {
    const double dx = u[2 * node] - reference[2 * node], dy = u[2 * node + 1] - reference[2 * node + 1];
    worst = std::max(worst, std::hypot(dx, dy));
  }
  for (std::size_t node = 0; 2 * node < reference.size(); ++node)
    largest = std::max(largest, std::hypot(reference[2 * node], reference[2 * node + 1]));
  return worst / largest;
}

struct RefineRun {
  std::string label;
  double threshold = -1;  // -1: not an adaptive run
  int cells = 0, passes = 0;
  std::vector<int> leaves_per_level;  // hierarchy leaves (transition triangles not counted)
  double error = 0, solve_seconds = 0, indicator_seconds = 0, refine_seconds = 0;
};

/// Refines every leaf `levels` times: the uniformly refined reference.
RefineRun uniform(const Mesh& coarse, const Scene& scene, int levels, std::vector<double>& displacement) {
  HierarchicalMesh hierarchy(coarse);
  for (int level = 0; level < levels; ++level) {
    std::vector<int> every(hierarchy.leaf_mesh().cell_count());
    for (std::size_t cell = 0; cell < every.size(); ++cell) every[cell] = static_cast<int>(cell);
    hierarchy.refine(every);
  }
  const Solution solution = solve(hierarchy.leaf_mesh(), scene);
  displacement = solution.displacement;
  RefineRun run;
  run.label = levels == 0 ? "coarse" : "uniform level " + std::to_string(levels);
  run.cells = hierarchy.leaf_mesh().cell_count();
  run.leaves_per_level = hierarchy.leaves_per_level();
  run.passes = 1;
  run.solve_seconds = solution.seconds;
  return run;
}

/// Solve, R_ZZ, refine the cells at or above threshold x the largest, until
/// nothing changes (or every marked cell is at kMaxLevel).
RefineRun adaptive(const Mesh& coarse, const Scene& scene, double threshold, const std::vector<double>& reference) {
  HierarchicalMesh hierarchy(coarse);
  RefineRun run;
  run.threshold = threshold;
  char label[64];
  std::snprintf(label, sizeof label, "R_ZZ >= %.2f max", threshold);
  run.label = label;
  Solution solution;
  for (;;) {
    solution = solve(hierarchy.leaf_mesh(), scene);
    run.solve_seconds += solution.seconds;
    ++run.passes;
    const Model model(hierarchy.leaf_mesh(), scene.model);
    auto start = Clock::now();
    const std::vector<int> marked = select_cells_at_threshold(zz_indicator(model, solution.displacement), threshold);
    run.indicator_seconds += std::chrono::duration<double>(Clock::now() - start).count();
    const int before = hierarchy.leaf_mesh().cell_count();
    start = Clock::now();
    hierarchy.refine(marked, kMaxLevel);
    run.refine_seconds += std::chrono::duration<double>(Clock::now() - start).count();
    if (hierarchy.leaf_mesh().cell_count() == before) break;
  }
  run.cells = hierarchy.leaf_mesh().cell_count();
  run.leaves_per_level = hierarchy.leaves_per_level();
  run.error = coarse_node_error(solution.displacement, reference, coarse.node_count());
  return run;
}

/// "a/b/c": the cells of each level.
std::string levels_text(const std::vector<int>& per_level) {
  std::string text;
  for (std::size_t level = 0; level < per_level.size(); ++level)
    text += (level ? "/" : "") + std::to_string(per_level[level]);
  return text;
}

void print_run(const RefineRun& run) {
  std::printf("%-20s %7d %-18s %6d %10.4f %9.1f %9.1f %9.1f\n", run.label.c_str(), run.cells,
              levels_text(run.leaves_per_level).c_str(), run.passes, 100 * run.error, 1e3 * run.solve_seconds,
              1e3 * run.indicator_seconds, 1e3 * run.refine_seconds);
}

// Figures with six significant digits, as always written.
Json json_of(const RefineRun& r) {
  return {{"label", r.label},
          {"threshold", r.threshold >= 0 ? number(r.threshold, 6) : Json(nullptr)},
          {"cells", r.cells},
          {"leaves_per_level", r.leaves_per_level},
          {"passes", r.passes},
          {"error", number(r.error, 6)},
          {"solve_seconds", number(r.solve_seconds, 6)},
          {"indicator_seconds", number(r.indicator_seconds, 6)},
          {"refine_seconds", number(r.refine_seconds, 6)}};
}

Json json_of(const std::vector<RefineRun>& runs, const Mesh& coarse, const Json& indentation) {
  Json plate = Json::array();
  for (const RefineRun& run : runs) plate.push_back(json_of(run));
  return {{"machine", cpu_model()},
          {"threads", omp_get_max_threads()},
          {"coarse_cells", coarse.cell_count()},
          {"max_level", kMaxLevel},
          {"runs", plate},
          {"indentation", indentation},
          {"metadata", metadata()}};
}

bool parse(const std::vector<std::string>& args, Options& options, int& exit_code) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") {
      std::fputs(kUsage, stdout);
      exit_code = 0;
      return false;
    }
    if (a == "--quick") {
      options.quick = true;
    } else if (a == "--json" && i + 1 < args.size()) {
      options.json = args[++i];
    } else {
      std::fprintf(stderr, "tensormass bench refine: unexpected argument '%s'\n%s", a.c_str(), kUsage);
      exit_code = 2;
      return false;
    }
  }
  return true;
}

}  // namespace

int refine_command(const std::vector<std::string>& args) {
  Options options;
  int exit_code = 0;
  if (!parse(args, options, exit_code)) return exit_code;
  const Mesh coarse = plate_mesh(options.quick ? 10 : 20);
  const Scene scene = plate_scene();
  std::printf("# tensormass bench refine%s\n\n%s, %d OpenMP threads (defaults)\n", options.quick ? " --quick" : "",
              cpu_model().c_str(), omp_get_max_threads());
  std::printf(
      "2D plate 10 x 5 cm, %d quad4, E 5 kPa, nu 0.45, bottom fixed, 2 cm probe 5 mm into the top, static Hooke.\n"
      "error: largest displacement difference at the coarse mesh's %d nodes against the uniform level-%d mesh,\n"
      "over its largest displacement. cells: of the mesh solved last (transition triangles included).\n"
      "Times, summed over the passes: model setup and solve, the indicator, the refinement.\n\n",
      coarse.cell_count(), coarse.node_count(), kMaxLevel);
  std::printf("%-20s %7s %-18s %6s %10s %9s %9s %9s\n", "run", "cells", "leaves per level", "passes", "error %",
              "solve ms", "R_ZZ ms", "refine ms");
  std::vector<RefineRun> runs;
  try {
    std::vector<double> reference, coarse_solution;
    RefineRun fine = uniform(coarse, scene, kMaxLevel, reference);
    RefineRun plain = uniform(coarse, scene, 0, coarse_solution);
    plain.error = coarse_node_error(coarse_solution, reference, coarse.node_count());
    runs = {plain, fine};
    print_run(plain);
    print_run(fine);
    const std::vector<double> thresholds =
        options.quick ? std::vector<double>{0.3} : std::vector<double>{0.1, 0.2, 0.3, 0.5};
    for (const double threshold : thresholds) {
      runs.push_back(adaptive(coarse, scene, threshold, reference));
      print_run(runs.back());
    }
    std::printf("\ntargets: error <= %.1fx the coarse mesh's with < %.1fx the reference's cells\n", kErrorTarget,
                kCellTarget);
    for (std::size_t i = 2; i < runs.size(); ++i) {
      const double error_ratio = runs[i].error / plain.error;
      const double cell_ratio = static_cast<double>(runs[i].cells) / fine.cells;
      std::printf("  %-20s error %.2fx, cells %.2fx -> %s\n", runs[i].label.c_str(), error_ratio, cell_ratio,
                  error_ratio <= kErrorTarget && cell_ratio < kCellTarget ? "met" : "MISSED");
    }
    std::printf(
        "refining costs at most one solve of the refined mesh (refine ms / solve ms, both summed over the passes):\n");
    for (std::size_t i = 2; i < runs.size(); ++i) {
      const double ratio = runs[i].refine_seconds / runs[i].solve_seconds;
      std::printf("  %-20s %.2f -> %s\n", runs[i].label.c_str(), ratio, ratio <= 1.0 ? "met" : "MISSED");
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "tensormass bench refine: %s\n", error.what());
    return 1;
  }
  std::fflush(stdout);
  const IndentationResult indentation = refine_indentation(options.quick);
  if (!options.json.empty()) {
    try {
      io::write_atomically(options.json,
                           [&](std::ostream& out) { out << json_text(json_of(runs, coarse, indentation.json)); });
    } catch (const std::exception& error) {
      std::fprintf(stderr, "tensormass bench refine: %s\n", error.what());
      return 1;
    }
  }
  return indentation.failed ? 1 : 0;
}

}  // namespace tensormass::bench
