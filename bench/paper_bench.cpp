// `tensormass bench paper`: see paper_bench.hpp and docs/results/paper.md.
//
// Method. Every run is a whole simulation from rest (the laws switch during
// it). One repetition runs every configuration of a beam once, in a fixed
// order, so slow drifts of a shared machine hit them alike; the figures
// quoted are medians over repetitions. A step's time is the wall time from
// the end of the previous step to the end of this one's adaptivity update
// (solve + criteria + switches), on one thread; the first step (CHOLMOD's
// symbolic analysis, first touch) is not counted. Displacements are
// recorded in the first repetition only (all repetitions are identical).
#include "paper_bench.hpp"

#include <dlfcn.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bench_metadata.hpp"
#include "machine_info.hpp"
#include "paper_report.hpp"
#include "tensormass/adaptivity/adaptivity.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/integrators/integrators.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/meshing/beam.hpp"
#include "tensormass/model/model.hpp"
#include "tensormass/scene/scene.hpp"

#ifndef TENSORMASS_BENCH_BUILD_INFO
#define TENSORMASS_BENCH_BUILD_INFO "unknown build flags"
#endif
#ifndef TENSORMASS_PAPER_SOURCE_DIR
#define TENSORMASS_PAPER_SOURCE_DIR "."
#endif

namespace tensormass::bench {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr const char* kUsage =
    "usage: tensormass bench paper [--quick | --smoke] [--json FILE] [--out DIR] [--repetitions N] [--no-3d] "
    "[--no-plots]\n"
    "  --quick          fewer repetitions and smaller 3D beams (about 2 minutes)\n"
    "  --smoke          a 12 x 2 quad beam, 10 steps, one repetition (CI, a few seconds)\n"
    "  --json FILE      also write the results as JSON to FILE\n"
    "  --out DIR        write paper.md, paper.json and the PNG plots to DIR (default: docs/results of the\n"
    "                   source tree for the full run; --quick and --smoke write nothing without --out)\n"
    "  --repetitions N  repetitions of every timed 2D run (default 7, --quick 3, --smoke 1; 3D: half)\n"
    "  --no-3d          only the 2D beams\n"
    "  --no-plots       do not run bench/plot_paper.py\n";

struct Options {
  bool quick = false, smoke = false, no_3d = false, plots = true;
  std::string json, out;
  int repetitions = 0;
};

// Same settings for every run.
constexpr double kPoisson = 0.3, kDensity = 1000.0, kGravity = 9.81;
constexpr double kDt = 0.01;
constexpr int kSteps = 150;    // 1.5 s
constexpr double kRamp = 1.0;  // gravity ramped in over 1 s ...
constexpr double kDampingMass =
    4;  // ... with Rayleigh mass damping (1/s; critical for the 6 m beam's first mode: about 5.6)
constexpr int kSmokeSteps = 10;
constexpr double kHuge = 1e300;                                  // a threshold that no element reaches
const std::vector<double> kStrainThresholds{0.015, 0.03, 0.06};  // R_EL, R_V, R_NL (the origin's 1.5, 3, 6 %)
const std::vector<double> kUpgradeFractions{0.5, 0.2, 0.05};     // R_S: thresholds upgrading these shares
constexpr int kCalibrationIterations = 12;

/// One beam of the experiment.
struct BeamCase {
  std::string name;
  BeamSpec spec;
  double young = 0;
  int origin = 0;  // the origin's element count to show beside (600, 300) or 0
};

/// One configuration (a row).
struct Config {
  std::string mode;  // hooke, stvk, R_EL, R_V, R_S, R_NL
  std::optional<double> threshold;
};

/// What one simulation gives.
struct RunResult {
  std::vector<double> step_ms;                                           // counted steps (all but the first)
  double criteria_seconds = 0, assembly_seconds = 0, solve_seconds = 0;  // counted steps
  int upgraded = 0;
  Trajectory trajectory;
  std::string failure;  // empty when it ran through
};

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// One thread for OpenMP and, when CHOLMOD loaded OpenBLAS, for BLAS too.
void single_thread() {
  omp_set_num_threads(1);
  using SetThreads = void (*)(int);
  if (auto set = reinterpret_cast<SetThreads>(::dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) set(1);
}

Scene make_scene(const BeamCase& beam, const Config& config, int steps) {
  Scene scene;
  scene.path = "bench-paper.yaml";
  scene.mesh = "bench-paper-beam";
  MaterialSpec material;
  material.law = config.mode == "stvk" ? "stvk" : "hooke";
  material.constants = elastic_constants(beam.young, kPoisson);
  material.density = kDensity;
  scene.model.materials = {material};
  scene.model.fixed = {"clamp"};
  scene.model.loads.gravity = {0.0, -kGravity, 0.0};
  scene.model.loads.profile.kind = ProfileKind::ramp;
  scene.model.loads.profile.duration = kRamp;
  scene.solver.damping_mass = kDampingMass;
  scene.solver.type = SolverType::implicit_euler;
  scene.solver.dt = kDt;
  scene.solver.steps = steps;
  scene.solver.newton_iterations = 1;
  scene.solver.linear.type = LinearSolverType::cholmod;
  if (config.threshold) {
    scene.adaptivity.enabled = true;
    scene.adaptivity.criteria = {{config.mode, *config.threshold, 0, ""}};
    scene.adaptivity.action = AdaptivityAction::upgrade;
    scene.adaptivity.every = 1;
    scene.adaptivity.blend_steps = 0;  // the origin switches at once
  }
  return scene;
}

/// Runs one simulation (the loop of run_scene, without files). `record`
/// keeps the displacements after each step; `criterion_max`, when given,
/// gets each element's largest value of the (single) criterion over the run.
RunResult simulate(const Mesh& mesh, const BeamCase& beam, const Config& config, int steps, bool record,
                   std::vector<double>* criterion_max = nullptr) {
  RunResult result;
  const Scene scene = make_scene(beam, config, steps);
  Model model(mesh, scene.model);
  const Assembler assembler(model);
  std::unique_ptr<Adaptivity> adaptivity;
  if (scene.adaptivity.enabled) adaptivity = std::make_unique<Adaptivity>(scene.adaptivity, model, assembler);
  auto linear = make_linear_solver(scene.solver.linear);
  SolveStatistics statistics;
  Integration run{model, assembler, *linear, scene.solver, statistics};
  State state;
  state.displacement.assign(model.dof_count(), 0.0);
  state.velocity.assign(model.dof_count(), 0.0);
  if (record) result.trajectory.reserve(steps);
  if (criterion_max) criterion_max->assign(model.cell_count(), 0.0);
  double criteria_after_first = 0;
  SolveStatistics after_first;
  auto mark = Clock::now();
  const StepObserver observer = [&](const State& s) {
    if (adaptivity) {
      adaptivity->advance_blends();
      adaptivity->update(s.displacement, s.step);
    }
    const auto now = Clock::now();
    if (s.step > 1) result.step_ms.push_back(1e3 * std::chrono::duration<double>(now - mark).count());
    else {
      after_first = statistics;
      if (adaptivity) criteria_after_first = adaptivity->criteria_seconds();
    }
    if (record) result.trajectory.push_back(s.displacement);
    if (criterion_max && adaptivity)
      for (const io::Field& field : adaptivity->cell_fields())
        if (field.name == config.mode)
          for (std::size_t c = 0; c < field.values.size(); ++c)
            (*criterion_max)[c] = std::max((*criterion_max)[c], field.values[c]);
    mark = Clock::now();
    return false;
  };
  try {
    solve_implicit(run, state, observer);
  } catch (const NumericalError& failure) {
    result.failure = failure.what();
  }
  if (adaptivity) result.criteria_seconds = adaptivity->criteria_seconds() - criteria_after_first;
  result.assembly_seconds = statistics.assembly_seconds - after_first.assembly_seconds;
  result.solve_seconds = statistics.solve_seconds - after_first.solve_seconds;
  for (int cell = 0; cell < model.cell_count(); ++cell)
    if (std::string(model.kernel(cell).law) == "stvk") ++result.upgraded;
  return result;
}

std::vector<BeamCase> beam_cases(const Options& options) {
  auto beam = [](std::string name, int dim, std::array<int, 3> cells, std::array<double, 3> size,
                 std::vector<BeamPhase> phases, double young, int origin) {
    BeamCase c;
    c.name = std::move(name);
    c.spec.dim = dim;
    c.spec.cells = cells;
    c.spec.size = size;
    c.spec.phases = std::move(phases);
    c.young = young;
    c.origin = origin;
    return c;
  };
  std::vector<BeamCase> cases;
  if (options.smoke) {
    cases.push_back(beam("quad 12x2", 2, {12, 2, 1}, {6.0, 1.0, 1.0}, {{"quad4", 1.0}}, 1e7, 0));
    return cases;
  }
  // Sag / L ~ rho g L^3 / (E H^2): the 3 m beam keeps the 6 m beam's sag
  // ratio with E / 8.
  cases.push_back(beam("quad 60x10", 2, {60, 10, 1}, {6.0, 1.0, 1.0}, {{"quad4", 1.0}}, 1e7, 600));
  cases.push_back(beam("quad 30x10", 2, {30, 10, 1}, {3.0, 1.0, 1.0}, {{"quad4", 1.0}}, 1.25e6, 300));
  if (options.no_3d) return cases;
  if (options.quick) {
    cases.push_back(beam("tet6 12x2x2", 3, {12, 2, 2}, {6.0, 1.0, 1.0}, {{"tet6", 1.0}}, 1e7, 0));
    cases.push_back(beam("hex8 16x3x3", 3, {16, 3, 3}, {6.0, 1.0, 1.0}, {{"hex8", 1.0}}, 1e7, 0));
    cases.push_back(beam("hex8+tet6 16x3x3", 3, {16, 3, 3}, {6.0, 1.0, 1.0}, {{"hex8", 0.5}, {"tet6", 0.5}}, 1e7, 0));
  } else {
    cases.push_back(beam("tet6 20x4x4", 3, {20, 4, 4}, {6.0, 1.0, 1.0}, {{"tet6", 1.0}}, 1e7, 0));
    cases.push_back(beam("hex8 40x4x4", 3, {40, 4, 4}, {6.0, 1.0, 1.0}, {{"hex8", 1.0}}, 1e7, 0));
    cases.push_back(beam("hex8+tet6 24x4x4", 3, {24, 4, 4}, {6.0, 1.0, 1.0}, {{"hex8", 0.5}, {"tet6", 0.5}}, 1e7, 0));
  }
  return cases;
}

/// The criteria overhead on one beam: pure Hooke against adaptive runs whose
/// threshold is never reached (nothing switches; the criteria still run).
struct Overhead {
  std::string criterion;
  double ms_per_step = 0, criteria_ms = 0, hooke_ms = 0;   // means per step (median over repetitions)
  double ms_median = 0, hooke_median = 0;                  // medians per step (median over repetitions)
  double added() const { return criteria_ms / hooke_ms; }  // the criteria's time over pure Hooke's step
};

struct BeamOutcome {
  std::vector<PaperRow> rows;
  std::vector<std::pair<double, double>> rs_thresholds;  // fraction asked, threshold
  std::vector<Overhead> overhead;
  double tip_stvk = 0, tip_hooke = 0;  // final tip deflection (m, positive down)
  bool ok = true;
};

double tip_deflection(const Mesh& mesh, int dim, const std::vector<double>& u) {
  const Group* tip = mesh.group("tip");
  if (tip == nullptr || tip->nodes.empty() || u.empty()) return NAN;
  double sum = 0.0;
  for (const int node : tip->nodes) sum += u[static_cast<std::size_t>(node) * dim + 1];
  return -sum / static_cast<double>(tip->nodes.size());
}

BeamOutcome run_beam(const BeamCase& beam, int steps, int repetitions, bool overhead) {
  BeamOutcome outcome;
  const Mesh mesh = make_beam(beam.spec);
  const int dim = beam.spec.dim;
  const double length = beam.spec.size[0];
  std::printf("\n== %s: %d elements, %d nodes, L = %g m, E = %g Pa ==\n", beam.name.c_str(), mesh.cell_count(),
              mesh.node_count(), length, beam.young);
  std::fflush(stdout);

  // R_S thresholds: geometric bisection on (untimed) adaptive runs until
  // the elements upgraded at the end are within 25 % of the share asked,
  // starting from the bracket of each element's largest R_S over a pure
  // Hooke run (R_S evaluated, nothing switching).
  std::vector<double> rs_max;
  const auto t0 = Clock::now();
  simulate(mesh, beam, {"R_S", kHuge}, steps, false, &rs_max);
  const int cells = mesh.cell_count();
  for (double fraction : kUpgradeFractions) {
    double lo = *std::min_element(rs_max.begin(), rs_max.end()) * 0.5;
    double hi = *std::max_element(rs_max.begin(), rs_max.end()) * 1.01;
    double best = upgrade_threshold(rs_max, fraction), best_miss = std::numeric_limits<double>::infinity();
    double t = best;
    const int iterations = beam.spec.dim == 2 ? kCalibrationIterations : kCalibrationIterations / 2;
    for (int iteration = 0; iteration < iterations; ++iteration) {
      const int upgraded = simulate(mesh, beam, {"R_S", t}, steps, false).upgraded;
      const double share = static_cast<double>(upgraded) / cells;
      const double miss = std::abs(std::log(std::max(share, 0.5 / cells) / fraction));
      if (miss < best_miss) {
        best_miss = miss;
        best = t;
      }
      if (std::abs(share - fraction) <= 0.25 * fraction) break;
      (share > fraction ? lo : hi) = t;
      t = std::sqrt(lo * hi);
    }
    outcome.rs_thresholds.push_back({fraction, best});
  }
  std::vector<Config> configs{{"hooke", std::nullopt}, {"stvk", std::nullopt}};
  for (const char* criterion : {"R_EL", "R_V"})
    for (double t : kStrainThresholds) configs.push_back({criterion, t});
  for (const auto& [fraction, t] : outcome.rs_thresholds) configs.push_back({"R_S", t});
  for (double t : kStrainThresholds) configs.push_back({"R_NL", t});
  const std::size_t first_overhead = configs.size();
  if (overhead)
    for (const char* criterion : {"R_EL", "R_V", "R_S", "R_NL"}) configs.push_back({criterion, kHuge});
  std::printf(
      "R_S thresholds (upgrading about 1/2, 1/5, 1/20 of the elements): %.4g, %.4g, %.4g N "
      "(calibration %.1f s)\n",
      outcome.rs_thresholds[0].second, outcome.rs_thresholds[1].second, outcome.rs_thresholds[2].second, since(t0));

  std::vector<std::vector<double>> means(configs.size()), medians(configs.size()), criteria(configs.size());
  std::vector<std::vector<double>> assembly(configs.size()), solve(configs.size());
  std::vector<RunResult> first(configs.size());
  for (int rep = 0; rep < repetitions; ++rep) {
    const auto start = Clock::now();
    // A different starting configuration each repetition, so that no
    // configuration always runs at the same point of a repetition.
    for (std::size_t k = 0; k < configs.size(); ++k) {
      const std::size_t i = (k + static_cast<std::size_t>(rep) * 5) % configs.size();
      RunResult r = simulate(mesh, beam, configs[i], steps, rep == 0);
      means[i].push_back(mean(r.step_ms));
      medians[i].push_back(median(r.step_ms));
      const double per_step = r.step_ms.empty() ? 0.0 : 1e3 / static_cast<double>(r.step_ms.size());
      criteria[i].push_back(r.criteria_seconds * per_step);
      assembly[i].push_back(r.assembly_seconds * per_step);
      solve[i].push_back(r.solve_seconds * per_step);
      if (rep == 0) first[i] = std::move(r);
    }
    std::printf("  repetition %d/%d: %.1f s\n", rep + 1, repetitions, since(start));
    std::fflush(stdout);
  }

  const RunResult& stvk = first[1];
  if (!first[0].failure.empty() || !stvk.failure.empty()) {
    std::fprintf(stderr, "tensormass bench paper: %s: a pure run failed: %s\n", beam.name.c_str(),
                 (first[0].failure.empty() ? stvk.failure : first[0].failure).c_str());
    outcome.ok = false;
  }
  outcome.tip_hooke =
      tip_deflection(mesh, dim, first[0].trajectory.empty() ? std::vector<double>{} : first[0].trajectory.back());
  outcome.tip_stvk =
      tip_deflection(mesh, dim, stvk.trajectory.empty() ? std::vector<double>{} : stvk.trajectory.back());
  std::printf("final tip deflection: Hooke %.3f m, StVK %.3f m (%.0f %% of L)\n", outcome.tip_hooke, outcome.tip_stvk,
              100 * outcome.tip_stvk / length);
  std::printf("%-6s %10s %11s %11s %11s %11s %11s %9s %11s   %s\n", "mode", "threshold", "mean ms", "median ms",
              "assembly ms", "solve ms", "criteria ms", "upgraded", "error", "note");
  for (std::size_t i = 0; i < first_overhead; ++i) {
    PaperRow row;
    row.beam = beam.name;
    row.elements = mesh.cell_count();
    row.mode = configs[i].mode;
    row.threshold = configs[i].threshold;
    row.ms_per_step = median(means[i]);
    row.ms_per_step_median = median(medians[i]);
    row.criteria_ms = median(criteria[i]);
    row.assembly_ms = median(assembly[i]);
    row.solve_ms = median(solve[i]);
    row.upgraded = first[i].upgraded;
    row.samples = means[i];
    row.error = first[i].failure.empty() && stvk.failure.empty()
                    ? trajectory_error(first[i].trajectory, stvk.trajectory, dim, length)
                    : NAN;
    std::printf("%-6s %10s %11.4f %11.4f %11.4f %11.4f %11.4f %9d %11.3e   %s\n", row.mode.c_str(),
                row.threshold ? std::to_string(*row.threshold).substr(0, 8).c_str() : "-", row.ms_per_step,
                row.ms_per_step_median, row.assembly_ms, row.solve_ms, row.criteria_ms, row.upgraded, row.error,
                first[i].failure.empty() ? "" : ("FAILED: " + first[i].failure).c_str());
    outcome.rows.push_back(std::move(row));
  }
  for (std::size_t i = first_overhead; i < configs.size(); ++i) {
    Overhead o;
    o.criterion = configs[i].mode;
    o.ms_per_step = median(means[i]);
    o.criteria_ms = median(criteria[i]);
    o.hooke_ms = median(means[0]);
    o.ms_median = median(medians[i]);
    o.hooke_median = median(medians[0]);
    std::printf(
        "overhead %-5s (threshold never reached): criteria %.4f ms per step = %.1f %% of pure Hooke's step; "
        "whole step %.4f ms vs Hooke %.4f (%+.1f %%), medians %.4f vs %.4f (%+.1f %%)\n",
        o.criterion.c_str(), o.criteria_ms, 100 * o.added(), o.ms_per_step, o.hooke_ms,
        100 * (o.ms_per_step / o.hooke_ms - 1), o.ms_median, o.hooke_median, 100 * (o.ms_median / o.hooke_median - 1));
    outcome.overhead.push_back(o);
  }
  std::fflush(stdout);
  return outcome;
}

/// 3D runs are 10 to 50 times dearer: fewer repetitions (3 of 7, 1 of 3).
int repetitions_3d(int repetitions_2d) { return std::max(1, repetitions_2d / 2); }

struct Target {
  std::string what;
  double value;
  std::string op;
  double limit;
  bool pass() const { return op == "<=" ? value <= limit : value >= limit; }
};

std::string fmt(const char* pattern, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

bool write_file(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream file(tmp);
    file << text;
    if (!file) {
      std::fprintf(stderr, "tensormass bench paper: cannot write %s\n", tmp.c_str());
      return false;
    }
  }
  std::error_code error;
  fs::rename(tmp, path, error);
  if (error) {
    std::fprintf(stderr, "tensormass bench paper: cannot write %s: %s\n", path.c_str(), error.message().c_str());
    return false;
  }
  return true;
}

bool parse(const std::vector<std::string>& args, Options& options, int& exit_code) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string* {
      if (i + 1 >= args.size() || args[i + 1].empty()) return nullptr;
      return &args[++i];
    };
    if (a == "--quick") options.quick = true;
    else if (a == "--smoke") options.smoke = true;
    else if (a == "--no-3d") options.no_3d = true;
    else if (a == "--no-plots") options.plots = false;
    else if (a == "--help" || a == "-h") {
      std::printf("%s", kUsage);
      exit_code = 0;
      return false;
    } else if (a == "--json" || a == "--out" || a == "--repetitions") {
      const std::string* v = value();
      if (!v) {
        std::fprintf(stderr, "tensormass bench paper: %s needs a value\n%s", a.c_str(), kUsage);
        exit_code = 2;
        return false;
      }
      if (a == "--json") options.json = *v;
      else if (a == "--out") options.out = *v;
      else {
        char* end = nullptr;
        const long n = std::strtol(v->c_str(), &end, 10);
        if (*end != '\0' || n < 1 || n > 1000) {
          std::fprintf(stderr, "tensormass bench paper: --repetitions needs an integer in [1, 1000]\n");
          exit_code = 2;
          return false;
        }
        options.repetitions = static_cast<int>(n);
      }
    } else {
      std::fprintf(stderr, "tensormass bench paper: unknown argument '%s'\n%s", a.c_str(), kUsage);
      exit_code = 2;
      return false;
    }
  }
  if (options.quick && options.smoke) {
    std::fprintf(stderr, "tensormass bench paper: --quick and --smoke exclude each other\n");
    exit_code = 2;
    return false;
  }
  return true;
}

// --- JSON ---------------------------------------------------------------------

Json settings_json(int steps, int repetitions) {
  return {{"dt", number(kDt)},
          {"steps", steps},
          {"newton_iterations", 1},
          {"linear", "cholmod"},
          {"poisson", number(kPoisson)},
          {"density", number(kDensity)},
          {"gravity", number(kGravity)},
          {"repetitions_2d", repetitions},
          {"repetitions_3d", repetitions_3d(repetitions)}};
}

Json beam_json(const BeamCase& beam, const BeamOutcome& outcome) {
  Json thresholds = Json::array();
  for (const auto& [fraction, threshold] : outcome.rs_thresholds)
    thresholds.push_back({{"fraction", number(fraction)}, {"threshold", number(threshold)}});
  return {{"beam", beam.name},
          {"dim", beam.spec.dim},
          {"length", number(beam.spec.size[0])},
          {"young", number(beam.young)},
          {"elements", outcome.rows.empty() ? 0 : outcome.rows[0].elements},
          {"tip_deflection_stvk", number(outcome.tip_stvk)},
          {"tip_deflection_hooke", number(outcome.tip_hooke)},
          {"r_s_thresholds", thresholds}};
}

Json overhead_json(const std::string& beam, const Overhead& o) {
  return {{"beam", beam},
          {"criterion", o.criterion},
          {"ms_per_step", number(o.ms_per_step)},
          {"hooke_ms_per_step", number(o.hooke_ms)},
          {"criteria_ms", number(o.criteria_ms)},
          {"ms_per_step_median", number(o.ms_median)},
          {"hooke_ms_per_step_median", number(o.hooke_median)}};
}

Json target_json(const Target& t) {
  return {{"what", t.what}, {"value", number(t.value)}, {"op", t.op}, {"limit", number(t.limit)}, {"pass", t.pass()}};
}

/// paper.json: the run, the machine, the settings, then per beam, the
/// overhead on the first one, the targets and every row.
Json paper_json(const std::string& run, int steps, int repetitions, const std::vector<BeamCase>& cases,
                const std::vector<BeamOutcome>& outcomes, const std::vector<Target>& targets,
                const std::vector<PaperRow>& rows) {
  Json beams = Json::array(), overhead = Json::array(), target_list = Json::array();
  for (std::size_t b = 0; b < cases.size(); ++b) beams.push_back(beam_json(cases[b], outcomes[b]));
  if (!outcomes.empty())
    for (const Overhead& o : outcomes[0].overhead) overhead.push_back(overhead_json(cases[0].name, o));
  for (const Target& t : targets) target_list.push_back(target_json(t));
  return {{"tool", "tensormass bench paper"},
          {"run", run},
          {"machine", cpu_model()},
          {"load_average", load_average()},
          {"build", TENSORMASS_BENCH_BUILD_INFO},
          {"threads", 1},
          {"settings", settings_json(steps, repetitions)},
          {"beams", beams},
          {"overhead", overhead},
          {"targets", target_list},
          {"rows", rows_json(rows)},
          {"metadata", metadata()}};
}

}  // namespace

int paper_command(const std::vector<std::string>& args) {
  Options options;
  int exit_code = 0;
  if (!parse(args, options, exit_code)) return exit_code;
  if (options.repetitions == 0) options.repetitions = options.smoke ? 1 : options.quick ? 3 : 7;
  if (options.out.empty() && !options.quick && !options.smoke)
    options.out = (fs::path(TENSORMASS_PAPER_SOURCE_DIR) / "docs" / "results").string();
  const int steps = options.smoke ? kSmokeSteps : kSteps;
  const auto start = Clock::now();
  single_thread();

  const std::string mode_name = options.smoke ? "--smoke" : options.quick ? "--quick" : "full";
  std::printf("tensormass bench paper (%s): the origin report's Table 1 and Figure 12\n", mode_name.c_str());
  std::printf("machine: %s, load average %s; build: %s; one thread\n", cpu_model().c_str(), load_average().c_str(),
              TENSORMASS_BENCH_BUILD_INFO);
  std::printf(
      "implicit Euler, dt = %g s, %d steps (first not timed), 1 Newton iteration per step, CHOLMOD; "
      "nu = %g, rho = %g kg/m^3, gravity %g m/s^2 (-y), clamped at x = 0; %d repetitions\n",
      kDt, steps, kPoisson, kDensity, kGravity, options.repetitions);

  std::vector<BeamCase> cases = beam_cases(options);
  std::vector<BeamOutcome> outcomes;
  std::vector<PaperRow> rows;
  bool ok = true;
  for (std::size_t b = 0; b < cases.size(); ++b) {
    const bool is_2d = cases[b].spec.dim == 2;
    const int reps = is_2d ? options.repetitions : repetitions_3d(options.repetitions);
    try {
      outcomes.push_back(run_beam(cases[b], steps, reps, b == 0));
    } catch (const std::exception& error) {
      std::fprintf(stderr, "tensormass bench paper: %s: %s\n", cases[b].name.c_str(), error.what());
      return 1;
    }
    ok = ok && outcomes.back().ok;
    rows.insert(rows.end(), outcomes.back().rows.begin(), outcomes.back().rows.end());
  }

  // Targets on the first beam (the 600-quad beam; the 12 x 2 beam in --smoke).
  const std::string main_beam = cases[0].name;
  std::vector<Target> targets;
  const PaperRow* hooke = find_row(rows, main_beam, "hooke");
  const PaperRow* stvk = find_row(rows, main_beam, "stvk");
  if (hooke && stvk) {
    // Both figures of each run: the mean per step (the origin's) and the
    // median per step (robust to the spikes of a shared machine).
    for (const bool use_median : {false, true}) {
      auto ms = [&](const PaperRow& r) { return use_median ? r.ms_per_step_median : r.ms_per_step; };
      const std::string what = use_median ? "median" : "mean";
      targets.push_back({main_beam + ": StVK / Hooke, " + what + " ms per step", ms(*stvk) / ms(*hooke), "<=", 2.5});
      double worst_outside = 0;  // largest excursion outside [Hooke, StVK] relative to the bound
      std::string worst_run = "none";
      for (const PaperRow& r : rows) {
        if (r.beam != main_beam || !r.threshold) continue;
        double excursion = 0;
        if (ms(r) > ms(*stvk)) excursion = ms(r) / ms(*stvk) - 1;
        if (ms(r) < ms(*hooke)) excursion = 1 - ms(r) / ms(*hooke);
        if (excursion > worst_outside) {
          worst_outside = excursion;
          worst_run = r.mode + " " + fmt("%.4g", *r.threshold);
        }
      }
      targets.push_back(
          {main_beam + ": adaptive runs outside [Hooke, StVK], " + what + " ms per step, worst (" + worst_run + ")",
           worst_outside, "<=", 0.10});
    }
    if (const PaperRow* el = find_row(rows, main_beam, "R_EL", 0.015))
      targets.push_back({main_beam + ": R_EL 0.015 error / Hooke's error", el->error / hooke->error, "<=", 0.5});
  }
  if (!outcomes.empty() && !outcomes[0].overhead.empty()) {
    double worst = 0;
    std::string which;
    for (const Overhead& o : outcomes[0].overhead)
      if (o.added() >= worst) {
        worst = o.added();
        which = o.criterion;
      }
    targets.push_back(
        {main_beam + ": criteria time / pure Hooke's mean step, worst criterion (" + which + ")", worst, "<=", 0.05});
  }
  std::printf("\n== Targets ==\n");
  for (const Target& t : targets)
    std::printf("%-4s %-80s %.3f (target %s %g)\n", t.pass() ? "PASS" : "MISS", t.what.c_str(), t.value, t.op.c_str(),
                t.limit);

  const std::string paper_text =
      json_text(paper_json(mode_name, steps, options.repetitions, cases, outcomes, targets, rows));
  if (!options.json.empty() && !write_file(options.json, paper_text)) return 1;

  if (!options.out.empty()) {
    std::error_code error;
    fs::create_directories(options.out, error);
    const fs::path out = options.out;
    if (!write_file(out / "paper.json", paper_text)) return 1;
    // The page: scripts/results/render_paper.py lays it out from the JSON.
    const std::string render = "/usr/bin/python3 '" + std::string(TENSORMASS_PAPER_SOURCE_DIR) +
                               "/scripts/results/render_paper.py' '" + (out / "paper.json").string() + "' > '" +
                               (out / "paper.md").string() + "'";
    if (std::system(render.c_str()) != 0) {
      std::fprintf(stderr, "tensormass bench paper: the page failed (%s)\n", render.c_str());
      return 1;
    }
    if (options.plots) {
      const std::string command = "/usr/bin/python3 '" + std::string(TENSORMASS_PAPER_SOURCE_DIR) +
                                  "/bench/plot_paper.py' '" + (out / "paper.json").string() + "' '" + out.string() +
                                  "'";
      if (std::system(command.c_str()) != 0)
        std::fprintf(stderr, "tensormass bench paper: the plots failed (%s)\n", command.c_str());
    }
    std::printf("wrote %s/paper.md, paper.json%s\n", out.c_str(), options.plots ? " and the plots" : "");
  }
  std::printf("total %.1f s\n", since(start));
  return ok ? 0 : 1;
}

}  // namespace tensormass::bench
