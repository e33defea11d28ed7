// `tensormass bench adaptive`: the adaptive model against the pure laws on
// local-deformation scenes (see adaptive_bench.hpp).
#include "adaptive_bench.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bench_metadata.hpp"
#include "machine_info.hpp"
#include "tensormass/adaptivity/adaptivity.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/integrators/integrators.hpp"
#include "tensormass/io/atomic_file.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/meshing/beam.hpp"
#include "tensormass/scene/scene.hpp"

namespace tensormass::bench {
namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kUsage =
    "usage: tensormass bench adaptive [--quick] [--rounds N] [--json FILE] [--only NAME]\n"
    "  --quick        smaller meshes and fewer steps (a smoke run; figures are not the targets')\n"
    "  --rounds N     run every run of a scene N times, round after round (default 3, 2 with\n"
    "                 --quick): times are medians, ratios medians of each round's ratio\n"
    "  --json FILE    also write the results as JSON to FILE (atomically)\n"
    "  --only NAME    one scene: indentation, needle, cantilever or quad-beam, each implicit (as\n"
    "                 named) or explicit (NAME-explicit); all eight by default; or needle-fine,\n"
    "                 the implicit needle in a mesh 3.4x larger (81,000 tets; only when named)\n";

struct Options {
  bool quick = false;
  int rounds = 0;  // 0: 3, or 2 with --quick
  std::string json;
  std::string only;
};

/// One scene and the runs to compare on it.
struct Case {
  std::string name;
  std::string what;  // one line: mesh, material, loading
  Mesh mesh;
  Scene scene;  // the pure linear run; adaptive runs add the criterion and the ladder
  std::vector<std::string> ladder;
  std::string criterion = "R_NL";
  std::vector<double> thresholds;
  /// Adaptive runs with R_P (the stress the linear law gets wrong, over E) instead of `criterion`.
  std::vector<double> stress_thresholds;
  /// Runs on the ladder [linear, corotational, rich]: R_NL (rotation or
  /// strain) asks for corotational, R_E (strain alone) for the rich law.
  std::vector<std::pair<double, double>> corotational_thresholds;  // (R_NL, R_E)
  /// Pure runs of other laws, for their cost and error beside the ladder's.
  std::vector<std::string> other_laws = {"corotational"};
  double error_target = 0.01;  // adaptive error at most this ...
  double cost_target = 0.5;    // ... at at most this fraction of the rich law's step
  int every = 1;               // adaptivity.every of the adaptive runs
};

/// What one run gives.
struct Run {
  std::string label;
  std::optional<double> threshold;
  double evaluated_share = 1;  // cells the criteria screen evaluated, over cells x evaluations
  bool screened = true;        // false: the criteria evaluated on every cell (AdaptivitySettings::screen), the baseline
  double mean_ms = 0, assembly_ms = 0, solve_ms = 0, criteria_ms = 0;  // per step, medians over the rounds
  /// mean_ms over the rich run's of the same round: median, lowest and highest over the rounds
  double ratio = 0, ratio_low = 0, ratio_high = 0;
  int steps = 0;
  long linear_iterations = 0;
  int factorizations = 0;
  long switches = 0;
  std::map<std::string, int> cells_per_law;
  double error = 0;     // against the rich run
  double max_disp = 0;  // largest nodal displacement over all steps
  std::string failure;
  std::vector<std::vector<double>> trajectory;  // displacement after each step (the first round's)
};

/// One run of a scene: what simulate() is given.
struct RunPlan {
  std::string label;
  Scene scene;
  std::optional<double> threshold;
  bool screened = true;
};

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n == 0 ? 0.0 : n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// --- Scenes ------------------------------------------------------------------

MaterialSpec material(const std::string& law, double young, double poisson, double density) {
  MaterialSpec m;
  m.law = law;
  m.constants = elastic_constants(young, poisson);
  m.density = density;
  return m;
}

/// Hexahedra along x, y, z of the indentation's block, each cut into 6 tets.
constexpr std::array<int, 3> kBlockCells = {20, 10, 20};
/// The scene run only when named (--only): too long for the default set.
constexpr const char* kNeedleFine = "needle-fine";

/// A 10 x 5 x 10 cm soft block (E 5 kPa, nu 0.45) on a fixed base; a 2 x 2 cm
/// probe on the top face pushed 1.5 cm down over 0.5 s (implicit, dt 0.01).
/// `cells`: the block's hexahedra (10 x 5 x 10 with --quick).
Case indentation(bool quick, std::array<int, 3> cells = kBlockCells) {
  Case c;
  c.name = "indentation";
  BeamSpec spec;
  spec.dim = 3;
  spec.cells = quick ? std::array<int, 3>{10, 5, 10} : cells;
  spec.size = {0.1, 0.05, 0.1};
  spec.phases = {{"tet6", 1.0}};
  c.mesh = make_beam(spec);
  const double eps = 1e-9;
  c.mesh.add_node_group("base", [&](double, double y, double) { return y < eps; });
  c.mesh.add_node_group("probe", [&](double x, double y, double z) {
    return y > 0.05 - eps && std::abs(x - 0.05) <= 0.01 + eps && std::abs(z - 0.05) <= 0.01 + eps;
  });
  Scene& s = c.scene;
  s.path = "bench-adaptive-indentation.yaml";
  s.model.materials = {material("hooke", 5e3, 0.45, 1000)};
  s.model.fixed = {"base"};
  PrescribedSpec probe;
  probe.region = "probe";
  probe.displacement = {0.0, -0.015, 0.0};
  probe.profile.kind = ProfileKind::ramp;
  probe.profile.duration = 0.5;
  s.model.prescribed = {probe};
  s.solver.type = SolverType::implicit_euler;
  s.solver.dt = 0.01;
  s.solver.steps = quick ? 20 : 50;
  if (quick) s.model.prescribed[0].profile.duration = 0.2;
  c.ladder = {"hooke", "neohookean"};
  c.thresholds = {0.003, 0.01, 0.03};
  c.stress_thresholds = {0.05, 0.1, 0.2};
  c.corotational_thresholds = {{0.003, 0.01}, {0.003, 0.03}};
  // StVK inverts under the probe; stable neo-Hookean is the
  // inversion-safe alternative to the rich law.
  c.other_laws = {"corotational", "stvk", "stable_neohookean"};
  c.what = std::to_string(c.mesh.cell_count()) + " tet4, E 5 kPa, nu 0.45, 2 x 2 cm probe 1.5 cm into 5 cm";
  return c;
}

/// The indentation's block under a 1 x 1 cm needle pushed 1 cm down: a
/// non-linear region that is a small part of the mesh (3 to 17 % of the
/// cells climb), the case the adaptive model is made for.
Case needle(bool quick, std::array<int, 3> cells = kBlockCells) {
  Case c = indentation(quick, cells);
  c.name = "needle";
  const double eps = 1e-9;
  c.mesh.add_node_group("needle", [&](double x, double y, double z) {
    return y > 0.05 - eps && std::abs(x - 0.05) <= 0.005 + eps && std::abs(z - 0.05) <= 0.005 + eps;
  });
  c.scene.path = "bench-adaptive-needle.yaml";
  c.scene.model.prescribed[0].region = "needle";
  c.scene.model.prescribed[0].displacement = {0.0, -0.01, 0.0};
  c.corotational_thresholds.clear();
  c.other_laws.clear();
  c.what = std::to_string(c.mesh.cell_count()) + " tet4, E 5 kPa, nu 0.45, 1 x 1 cm needle 1 cm into 5 cm";
  return c;
}

/// The needle in the same block cut 1.5x finer along each side (81,000
/// tets, 43,000 free dofs): the same non-linear region in a mesh 3.4x larger, as
/// in a patient-sized model. Run only when asked (--only needle-fine): a
/// whole factorisation there takes seconds.
Case needle_fine(bool quick) {
  Case c = needle(quick, {30, 15, 30});
  c.name = kNeedleFine;
  c.scene.path = "bench-adaptive-needle-fine.yaml";
  return c;
}

/// The same scene integrated explicitly (symplectic Euler, no linear
/// solve), as interactive surgical simulators run: dt is half the stable
/// step estimated for the linear law at rest, the criteria run every
/// `every` steps (a step moves the tissue little).
Case explicit_variant(Case c, int every) {
  c.name += "-explicit";
  Scene& s = c.scene;
  s.solver.type = SolverType::explicit_euler;
  Model model(c.mesh, s.model);
  const Assembler assembler(model);
  const double duration = s.solver.dt * s.solver.steps;
  s.solver.dt = 0.5 * estimate_stable_time_step(model, assembler);
  s.solver.steps = static_cast<int>(std::ceil(duration / s.solver.dt));
  s.solver.dt = duration / s.solver.steps;
  c.every = every;
  c.what += ", explicit dt " + std::to_string(s.solver.dt * 1e3).substr(0, 5) + " ms, criteria every " +
            std::to_string(every) + " steps";
  return c;
}

/// A beam clamped at x = 0 sagging under gravity (implicit, dt 0.01), ladder hooke -> stvk.
Case gravity_beam(const std::string& name, int dim, std::array<int, 3> cells, std::array<double, 3> size,
                  const std::string& cut, double young, int steps) {
  Case c;
  c.name = name;
  BeamSpec spec;
  spec.dim = dim;
  spec.cells = cells;
  spec.size = size;
  spec.phases = {{cut, 1.0}};
  c.mesh = make_beam(spec);
  Scene& s = c.scene;
  s.path = "bench-adaptive-" + name + ".yaml";
  s.model.materials = {material("hooke", young, 0.3, 1000)};
  s.model.fixed = {"clamp"};
  s.model.loads.gravity = {0.0, -9.81, 0.0};
  s.solver.type = SolverType::implicit_euler;
  s.solver.dt = 0.01;
  s.solver.steps = steps;
  c.ladder = {"hooke", "stvk"};
  c.cost_target = 0.7;
  return c;
}

/// The 3D cantilever: 5 x 1 x 1 m, 8,640 tets, E 20 MPa, 150 steps.
Case cantilever(bool quick) {
  Case c = gravity_beam("cantilever", 3, quick ? std::array<int, 3>{15, 3, 3} : std::array<int, 3>{30, 6, 8},
                        {5.0, 1.0, 1.0}, "tet6", 2e7, quick ? 30 : 150);
  c.thresholds = {0.003, 0.01, 0.03};
  c.stress_thresholds = {0.003, 0.01, 0.03};
  c.corotational_thresholds = {{0.001, 0.003}, {0.003, 0.01}};
  c.what = std::to_string(c.mesh.cell_count()) + " tet4, 5 x 1 x 1 m, E 20 MPa, gravity";
  return c;
}

/// The origin's 600-quad beam: 6 x 1 m, E 10 MPa.
Case quad_beam(bool quick) {
  Case c = gravity_beam("quad-beam", 2, {60, 10, 1}, {6.0, 1.0, 1.0}, "quad4", 1e7, quick ? 30 : 150);
  c.thresholds = {0.005, 0.015, 0.03};
  c.corotational_thresholds = {{0.001, 0.005}, {0.005, 0.015}};
  c.what = "600 quad4, 6 x 1 m, E 10 MPa, gravity";
  return c;
}

// --- Runs --------------------------------------------------------------------

Scene run_scene_of(const Case& c, const std::string& law, std::optional<double> threshold,
                   const std::string& criterion = "") {
  Scene s = c.scene;
  s.model.materials[0].law = law;
  if (threshold) {
    s.adaptivity.enabled = true;
    s.adaptivity.criteria = {{criterion.empty() ? c.criterion : criterion, *threshold, 0, ""}};
    s.adaptivity.ladder = c.ladder;
    s.adaptivity.every = c.every;
  }
  return s;
}

/// An adaptive run on [linear, corotational, rich] with R_NL and R_E.
Scene corotational_scene_of(const Case& c, double nonlinear, double strain) {
  Scene s = run_scene_of(c, c.ladder.front(), std::nullopt);
  s.adaptivity.enabled = true;
  s.adaptivity.criteria = {{"R_NL", nonlinear, 0, "corotational"}, {"R_E", strain, 0, ""}};
  s.adaptivity.ladder = {c.ladder.front(), "corotational", c.ladder.back()};
  s.adaptivity.every = c.every;
  return s;
}

/// One run; its trajectory is kept when `record` (the later rounds only time).
Run simulate(const Case& c, const RunPlan& plan, bool record) {
  const Scene& scene = plan.scene;
  Run run;
  run.label = plan.label;
  run.threshold = plan.threshold;
  run.screened = plan.screened;
  Model model(c.mesh, scene.model);
  const Assembler assembler(model);
  std::unique_ptr<Adaptivity> adaptivity;
  if (scene.adaptivity.enabled) adaptivity = std::make_unique<Adaptivity>(scene.adaptivity, model, assembler);
  auto linear = make_linear_solver(scene.solver.linear);
  describe_free_nodes(*linear, model);  // as Simulation does (used by linear.type: petsc)
  SolveStatistics statistics;
  Integration integration{model, assembler, *linear, scene.solver, statistics};
  State state;
  state.displacement.assign(model.dof_count(), 0.0);
  state.velocity.assign(model.dof_count(), 0.0);
  double bookkeeping_seconds = 0.0;
  const auto start = Clock::now();
  if (adaptivity) adaptivity->start(state.displacement);
  const StepObserver observer = [&](const State& s) {
    if (adaptivity) {
      adaptivity->advance_blends();
      adaptivity->update(s.displacement, s.step);
    }
    // The copy is the benchmark's, not the run's: its time is taken out
    // (it is a sizeable part of an explicit step of a fraction of a ms).
    ++run.steps;
    if (!record) return false;
    const auto copy_start = Clock::now();
    run.trajectory.push_back(s.displacement);
    bookkeeping_seconds += std::chrono::duration<double>(Clock::now() - copy_start).count();
    return false;
  };
  try {
    if (scene.solver.type == SolverType::explicit_euler) solve_explicit(integration, state, observer);
    else solve_implicit(integration, state, observer);
  } catch (const NumericalError& failure) {
    run.failure = failure.what();
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count() - bookkeeping_seconds;
  const double steps = std::max(1, run.steps);
  run.mean_ms = 1e3 * seconds / steps;
  run.assembly_ms = 1e3 * statistics.assembly_seconds / steps;
  run.solve_ms = 1e3 * statistics.solve_seconds / steps;
  run.criteria_ms = adaptivity ? 1e3 * adaptivity->criteria_seconds() / steps : 0.0;
  run.linear_iterations = statistics.linear_iterations;
  run.factorizations = statistics.factorizations;
  run.switches = adaptivity ? adaptivity->total_switches() : 0;
  if (const CriteriaScreen* screen = adaptivity ? adaptivity->screen() : nullptr; screen && screen->evaluations() > 0)
    run.evaluated_share = static_cast<double>(screen->evaluated_cells()) / screen->evaluations() / model.cell_count();
  for (int cell = 0; cell < model.cell_count(); ++cell) ++run.cells_per_law[model.kernel(cell).law];
  return run;
}

double node_distance(const std::vector<double>& a, const std::vector<double>& b, int node, int d) {
  double squared = 0.0;
  for (int k = 0; k < d; ++k) squared += (a[node * d + k] - b[node * d + k]) * (a[node * d + k] - b[node * d + k]);
  return std::sqrt(squared);
}

/// Largest nodal displacement of a run over all steps.
double largest_displacement(const Run& run, int d) {
  const std::vector<double> zero(run.trajectory.empty() ? 0 : run.trajectory[0].size(), 0.0);
  double largest = 0.0;
  for (const auto& u : run.trajectory)
    for (int node = 0; node < static_cast<int>(u.size()) / d; ++node)
      largest = std::max(largest, node_distance(u, zero, node, d));
  return largest;
}

/// Largest nodal distance to the reference over the steps both reached, over `scale`.
double trajectory_error(const Run& run, const Run& reference, int d, double scale) {
  double worst = 0.0;
  const std::size_t steps = std::min(run.trajectory.size(), reference.trajectory.size());
  for (std::size_t s = 0; s < steps; ++s)
    for (int node = 0; node < static_cast<int>(run.trajectory[s].size()) / d; ++node)
      worst = std::max(worst, node_distance(run.trajectory[s], reference.trajectory[s], node, d));
  return worst / scale;
}

std::string laws_text(const std::map<std::string, int>& cells) {
  std::string text;
  for (const auto& [law, count] : cells) text += (text.empty() ? "" : ", ") + std::to_string(count) + " " + law;
  return text;
}

// --- One scene ---------------------------------------------------------------

struct CaseResult {
  const Case* scene;
  std::vector<Run> runs;  // linear, rich, adaptive...
  bool pure_failed = false;
  int rounds = 1;
};

/// The runs of a scene: pure linear, pure rich, the other pure laws, the
/// adaptive runs, the screen's baseline, the three-rung runs.
std::vector<RunPlan> plans_of(const Case& c) {
  const std::string& linear = c.ladder.front();
  const std::string& rich = c.ladder.back();
  std::vector<RunPlan> plans;
  plans.push_back({linear, run_scene_of(c, linear, std::nullopt), std::nullopt});
  plans.push_back({rich, run_scene_of(c, rich, std::nullopt), std::nullopt});
  for (const std::string& law : c.other_laws) plans.push_back({law, run_scene_of(c, law, std::nullopt), std::nullopt});
  char label[96];
  for (double t : c.thresholds) {
    std::snprintf(label, sizeof label, "adaptive %s %g", c.criterion.c_str(), t);
    plans.push_back({label, run_scene_of(c, linear, t), t});
  }
  if (!c.thresholds.empty()) {  // the middle threshold again with every cell evaluated: the screen's baseline
    const double t = c.thresholds[c.thresholds.size() / 2];
    std::snprintf(label, sizeof label, "adaptive %s %g, every cell evaluated", c.criterion.c_str(), t);
    plans.push_back({label, run_scene_of(c, linear, t), t, false});
    plans.back().scene.adaptivity.screen = false;
  }
  for (double t : c.stress_thresholds) {
    std::snprintf(label, sizeof label, "adaptive R_P %g", t);
    plans.push_back({label, run_scene_of(c, linear, t, "R_P"), t});
  }
  for (const auto& [nonlinear, strain] : c.corotational_thresholds) {
    std::snprintf(label, sizeof label, "3 rungs, R_NL %g -> corot., R_E %g -> %s", nonlinear, strain, rich.c_str());
    plans.push_back({label, corotational_scene_of(c, nonlinear, strain), nonlinear});
  }
  return plans;
}

/// Every plan once per round, round after round, so that the machine's
/// drift falls on all runs alike; the first round's runs keep their
/// trajectories and get the medians of the timings over the rounds, and the
/// median, lowest and highest of each round's ratio to the rich run (plans[1]).
std::vector<Run> run_rounds(const Case& c, const std::vector<RunPlan>& plans, int rounds) {
  std::vector<std::vector<Run>> timed(plans.size());
  for (int round = 0; round < rounds; ++round) {
    if (rounds > 1) std::fprintf(stderr, "  %s: round %d of %d\n", c.name.c_str(), round + 1, rounds);
    for (std::size_t p = 0; p < plans.size(); ++p) timed[p].push_back(simulate(c, plans[p], round == 0));
  }
  std::vector<Run> runs;
  for (std::size_t p = 0; p < plans.size(); ++p) {
    Run run = std::move(timed[p][0]);
    std::vector<double> mean, assembly, solve, criteria, ratio;
    for (int round = 0; round < rounds; ++round) {
      const Run& r = timed[p][round];
      mean.push_back(r.mean_ms);
      assembly.push_back(r.assembly_ms);
      solve.push_back(r.solve_ms);
      criteria.push_back(r.criteria_ms);
      ratio.push_back(r.mean_ms / (p == 1 ? run.mean_ms : timed[1][round].mean_ms));
    }
    if (p == 1) std::fill(ratio.begin(), ratio.end(), 1.0);
    run.mean_ms = median(mean);
    run.assembly_ms = median(assembly);
    run.solve_ms = median(solve);
    run.criteria_ms = median(criteria);
    run.ratio = median(ratio);
    run.ratio_low = *std::min_element(ratio.begin(), ratio.end());
    run.ratio_high = *std::max_element(ratio.begin(), ratio.end());
    runs.push_back(std::move(run));
  }
  return runs;
}

CaseResult run_case(const Case& c, int rounds) {
  CaseResult result{&c, {}, false, rounds};
  std::printf("\n## %s: %s, %d steps, ladder [", c.name.c_str(), c.what.c_str(), c.scene.solver.steps);
  for (std::size_t r = 0; r < c.ladder.size(); ++r) std::printf("%s%s", r ? ", " : "", c.ladder[r].c_str());
  std::printf("], criterion %s%s\n\n", c.criterion.c_str(), c.stress_thresholds.empty() ? "" : " or R_P");
  std::fflush(stdout);
  result.runs = run_rounds(c, plans_of(c), rounds);
  const int d = c.mesh.dim;
  const Run& reference = result.runs[1];
  result.pure_failed = !result.runs[0].failure.empty() || !reference.failure.empty();
  const double scale = std::max(largest_displacement(reference, d), 1e-300);
  for (Run& run : result.runs) {
    run.max_disp = largest_displacement(run, d);
    run.error = trajectory_error(run, reference, d, scale);
  }
  std::printf("medians of %d rounds; x rich: the median of each round's ratio, and its range\n\n", rounds);
  std::printf(
      "| run | ms/step | x rich | range | assembly | solve | criteria | lin. its | factor. | cells per law (end) | "
      "error |\n");
  std::printf("|---|---:|---:|---|---:|---:|---:|---:|---:|---|---:|\n");
  for (const Run& run : result.runs) {
    std::printf("| %s | %.2f | %.2f | %.2f-%.2f | %.2f | %.2f | %.3f | %ld | %d | %s | %s |\n", run.label.c_str(),
                run.mean_ms, run.ratio, run.ratio_low, run.ratio_high, run.assembly_ms, run.solve_ms, run.criteria_ms,
                run.linear_iterations, run.factorizations, laws_text(run.cells_per_law).c_str(),
                run.failure.empty() ? (std::to_string(100.0 * run.error).substr(0, 5) + " %").c_str() : "failed");
    if (!run.failure.empty()) std::printf("|   | failed: %s ||||||||||\n", run.failure.c_str());
  }
  std::fflush(stdout);
  return result;
}

/// The screened run against its baseline (every cell evaluated, same threshold):
/// the criteria's cost, and whether the trajectories are the same bits.
void print_screen(const CaseResult& result) {
  const auto baseline = std::find_if(result.runs.begin(), result.runs.end(), [](const Run& r) { return !r.screened; });
  if (baseline == result.runs.end()) return;
  const auto screened = std::find_if(result.runs.begin(), result.runs.end(), [&](const Run& r) {
    return r.screened && r.threshold == baseline->threshold && r.label.rfind("adaptive", 0) == 0;
  });
  if (screened == result.runs.end()) return;
  const bool same = screened->trajectory == baseline->trajectory && screened->failure == baseline->failure;
  std::printf(
      "  criteria screen at %g: %.1f %% of the cells evaluated, %.4f ms a step against %.4f every cell "
      "evaluated (%.2fx), %.2f ms a step against %.2f; trajectories %s\n",
      *baseline->threshold, 100 * screened->evaluated_share, screened->criteria_ms, baseline->criteria_ms,
      screened->criteria_ms / std::max(baseline->criteria_ms, 1e-12), screened->mean_ms, baseline->mean_ms,
      same ? "identical" : "DIFFER");
}

/// The benchmark's targets on one scene; prints each, returns nothing (misses are reported, not fatal).
void print_targets(const CaseResult& result) {
  const Case& c = *result.scene;
  const Run& linear = result.runs[0];
  const Run* best = nullptr;  // cheapest adaptive run within the error target
  double worst_ratio = 0.0, worst_criteria = 0.0;
  for (const Run& run : result.runs) {
    if (!run.threshold || !run.failure.empty() || !run.screened) continue;  // pure runs, the screen's baseline
    worst_ratio = std::max(worst_ratio, run.ratio);
    worst_criteria = std::max(worst_criteria, run.criteria_ms / linear.mean_ms);
    if (run.error <= c.error_target && (!best || run.ratio < best->ratio)) best = &run;
  }
  std::printf("\ntargets (%s):\n", c.name.c_str());
  if (best)
    std::printf("  adaptive within %.0f %% of %s at <= %.2fx its step: %s, %.3f %% at %.2fx -> %s\n",
                100 * c.error_target, c.ladder.back().c_str(), c.cost_target, best->label.c_str(), 100 * best->error,
                best->ratio, best->ratio <= c.cost_target ? "met" : "MISSED");
  else
    std::printf("  adaptive within %.0f %% of %s at <= %.2fx its step: no adaptive run within %.0f %% -> MISSED\n",
                100 * c.error_target, c.ladder.back().c_str(), c.cost_target, 100 * c.error_target);
  std::printf("  no adaptive run slower than %s x 1.05: worst %.2fx -> %s\n", c.ladder.back().c_str(), worst_ratio,
              worst_ratio <= 1.05 ? "met" : "MISSED");
  std::printf("  criteria <= 5 %% of a %s step: worst %.1f %% -> %s\n", c.ladder.front().c_str(), 100 * worst_criteria,
              worst_criteria <= 0.05 ? "met" : "MISSED");
  print_screen(result);
}

// --- JSON and the command ----------------------------------------------------

// Figures with six significant digits, as always written.
Json json_of(const Run& run) {
  Json cells_per_law = Json::object();
  for (const auto& [law, count] : run.cells_per_law) cells_per_law[law] = count;
  return {{"label", run.label},
          {"threshold", run.threshold ? number(*run.threshold, 6) : Json(nullptr)},
          {"screened", run.screened},
          {"ms_per_step", number(run.mean_ms, 6)},
          {"ratio", number(run.ratio, 6)},
          {"ratio_low", number(run.ratio_low, 6)},
          {"ratio_high", number(run.ratio_high, 6)},
          {"assembly_ms", number(run.assembly_ms, 6)},
          {"solve_ms", number(run.solve_ms, 6)},
          {"criteria_ms", number(run.criteria_ms, 6)},
          {"error", number(run.error, 6)},
          {"switches", run.switches},
          {"failed", !run.failure.empty()},
          {"cells_per_law", cells_per_law}};
}

Json json_of(const CaseResult& result) {
  const Case& c = *result.scene;
  Json runs = Json::array();
  for (const Run& run : result.runs) runs.push_back(json_of(run));
  return {{"name", c.name},
          {"rounds", result.rounds},
          {"cells", c.mesh.cell_count()},
          {"steps", c.scene.solver.steps},
          {"runs", runs}};
}

Json json_of(const std::vector<CaseResult>& results) {
  Json scenes = Json::array();
  for (const CaseResult& result : results) scenes.push_back(json_of(result));
  return {{"machine", cpu_model()}, {"threads", omp_get_max_threads()}, {"scenes", scenes}, {"metadata", metadata()}};
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
    } else if (a == "--rounds" && i + 1 < args.size()) {
      const std::string& value = args[++i];
      char* end = nullptr;
      const long rounds = std::strtol(value.c_str(), &end, 10);
      if (value.empty() || *end != '\0' || rounds < 1 || rounds > 100) {
        std::fprintf(stderr, "tensormass bench adaptive: --rounds wants a whole number from 1 to 100, not '%s'\n",
                     value.c_str());
        exit_code = 2;
        return false;
      }
      options.rounds = static_cast<int>(rounds);
    } else if ((a == "--json" || a == "--only") && i + 1 < args.size()) {
      (a == "--json" ? options.json : options.only) = args[++i];
    } else {
      std::fprintf(stderr, "tensormass bench adaptive: unexpected argument '%s'\n%s", a.c_str(), kUsage);
      exit_code = 2;
      return false;
    }
  }
  const std::vector<std::string> names = {"indentation", "needle", "cantilever", "quad-beam"};
  if (!options.only.empty() && options.only != kNeedleFine &&
      std::none_of(names.begin(), names.end(), [&](const std::string& name) {
        return options.only == name || options.only == name + "-explicit";
      })) {
    std::fprintf(stderr, "tensormass bench adaptive: unknown scene '%s'\n%s", options.only.c_str(), kUsage);
    exit_code = 2;
    return false;
  }
  return true;
}

}  // namespace

int adaptive_command(const std::vector<std::string>& args) {
  Options options;
  int exit_code = 0;
  if (!parse(args, options, exit_code)) return exit_code;
  std::printf("# tensormass bench adaptive%s\n\n%s, %d OpenMP threads (defaults)\n", options.quick ? " --quick" : "",
              cpu_model().c_str(), omp_get_max_threads());
  std::printf(
      "ms/step: wall time of the whole step (assembly, solve, criteria, rest); error: largest nodal\n"
      "distance to the pure rich law over all steps / its largest displacement.\n");
  std::vector<Case> cases;
  const auto wanted = [&](const std::string& name) { return options.only.empty() || options.only == name; };
  for (Case base :
       {indentation(options.quick), needle(options.quick), cantilever(options.quick), quad_beam(options.quick)}) {
    if (wanted(base.name + "-explicit")) cases.push_back(explicit_variant(base, 10));
    if (wanted(base.name)) cases.push_back(std::move(base));
  }
  if (options.only == kNeedleFine) cases.push_back(needle_fine(options.quick));
  const int rounds = options.rounds > 0 ? options.rounds : options.quick ? 2 : 3;
  std::vector<CaseResult> results;
  bool failed = false;
  for (const Case& c : cases) {
    results.push_back(run_case(c, rounds));
    print_targets(results.back());
    failed = failed || results.back().pure_failed;
  }
  std::printf("\nthe thorax deep breath (scene 2) runs through Python: bench/thorax_deep_breath.py\n");
  if (!options.json.empty()) {
    try {
      io::write_atomically(options.json, [&](std::ostream& out) { out << json_text(json_of(results)); });
    } catch (const std::exception& error) {
      std::fprintf(stderr, "tensormass bench adaptive: %s\n", error.what());
      return 1;
    }
  }
  return failed ? 1 : 0;
}

}  // namespace tensormass::bench
