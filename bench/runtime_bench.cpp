// `tensormass bench runtime`: see runtime_bench.hpp and docs/results/runtime.md.
//
// Method. Every figure is a median over repetitions taken in this process;
// configurations that are compared (tensormass vs ccx, Hooke vs StVK) are
// run alternately, so slow drifts of a shared machine hit them alike.
// Dynamic runs take one extra first step that is not counted (CHOLMOD's
// symbolic analysis, CG's cold start, first touch of the memory); its
// duration is reported separately.
#include "runtime_bench.hpp"

#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench_metadata.hpp"
#include "calculix_runner.hpp"
#include "machine_info.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/assembly/sparse_matrix.hpp"
#include "tensormass/integrators/integrators.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/meshing/beam.hpp"
#include "tensormass/model/model.hpp"
#include "tensormass/scene/scene.hpp"

#ifndef TENSORMASS_BENCH_BUILD_INFO
#define TENSORMASS_BENCH_BUILD_INFO "unknown build flags"
#endif

namespace tensormass::bench {

namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kUsage =
    "usage: tensormass bench runtime [--quick] [--json FILE] [--only NAME] [--threads N] [--ccx PATH] [--keep-ccx]\n"
    "                                [--scaling]\n"
    "  --quick        smaller problems and fewer repetitions (CI smoke test, well under a minute)\n"
    "  --json FILE    also write the results as JSON to FILE (atomically)\n"
    "  --only NAME    run one part: ccx, threads, implicit, quad, batch, spmv or scatter\n"
    "  --threads N    threads of tensormass AND ccx (OMP_NUM_THREADS) in the ccx comparison (default: the\n"
    "                 OpenMP default a user gets, all cores)\n"
    "  --ccx PATH     the CalculiX executable (default: $TENSORMASS_CCX, else ccx in PATH)\n"
    "  --keep-ccx     keep CalculiX's work directory (deck, .dat, .sta, log) and print where\n"
    "  --scaling      implicit steps up to a million tets (docs/results/scaling.md; several minutes)\n";

struct Options {
  bool quick = false;
  std::string json, only, ccx;  // ccx: "" = $TENSORMASS_CCX, else ccx in PATH
  int threads = 0;              // 0: the defaults
  bool keep_ccx = false;
  bool scaling = false;  // the implicit table up to a million tets
};

// Material of every run: soft solid, SI units.
constexpr double kPoisson = 0.3;
constexpr double kDensity = 1000.0;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (const double v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

/// Sets the OpenMP thread count for its lifetime (CHOLMOD's BLAS runs on
/// one thread whatever the count: solvers/cholmod_solver.cpp).
class Threads {
 public:
  explicit Threads(int count) : previous_(omp_get_max_threads()) { omp_set_num_threads(count); }
  ~Threads() { omp_set_num_threads(previous_); }
  Threads(const Threads&) = delete;
  Threads& operator=(const Threads&) = delete;

 private:
  int previous_;
};

/// The BLAS libraries mapped into this process (CHOLMOD's supernodal
/// factorisation runs in BLAS: its speed decides the CHOLMOD figures).
std::string loaded_blas() {
  std::ifstream maps("/proc/self/maps");
  std::string line, found;
  std::map<std::string, bool> seen;
  while (std::getline(maps, line)) {
    const auto slash = line.find('/');
    if (slash == std::string::npos) continue;
    const std::string path = line.substr(slash);
    const std::string name = path.substr(path.rfind('/') + 1);
    if (name.find("blas") == std::string::npos || seen[path]) continue;
    seen[path] = true;
    std::string canonical = path;
    if (char* real = ::realpath(path.c_str(), nullptr)) {
      canonical = real;
      std::free(real);
    }
    found += (found.empty() ? "" : ", ") + canonical;
  }
  if (found.empty()) return "none loaded";
  if (found.find("openblas") != std::string::npos) return found + " (OpenBLAS)";
  if (found.find("/blas/libblas") != std::string::npos) return found + " (reference BLAS, unoptimised)";
  return found;
}

// --- JSON ---------------------------------------------------------------------

/// A figure as this benchmark has always written it: six significant digits, null where not finite.
Json figure(double x) { return number(x, 6); }
Json figures(const std::vector<double>& values) { return numbers(values, 6); }

bool write_file_atomically(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".tmp";
  std::FILE* file = std::fopen(temporary.c_str(), "w");
  if (file == nullptr) return false;
  const bool written = std::fputs(text.c_str(), file) >= 0 && std::fflush(file) == 0 && !std::ferror(file);
  if (std::fclose(file) != 0 || !written || std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    return false;
  }
  return true;
}

// --- Targets ------------------------------------------------------------------

struct Target {
  std::string name;
  double value = NAN;
  std::string relation;  // "<=" or ">="
  double goal = 0;
  bool measured = false;
  bool pass() const { return measured && (relation == "<=" ? value <= goal : value >= goal); }
};

// --- Scenes and meshes ----------------------------------------------------------

Mesh beam_mesh(int dim, const std::string& cut, std::array<int, 3> cells, std::array<double, 3> size) {
  BeamSpec spec;
  spec.dim = dim;
  spec.cells = cells;
  spec.size = size;
  spec.phases = {{cut, 1.0}};
  return make_beam(spec);
}

/// A cantilever clamped at x = 0 under gravity along -y, one material everywhere.
Scene cantilever(const std::string& law, double young, double gravity, SolverType type) {
  Scene scene;
  scene.path = "bench-runtime.yaml";
  scene.mesh = "bench-runtime-beam";
  MaterialSpec material;
  material.law = law;
  material.constants = elastic_constants(young, kPoisson);
  material.density = kDensity;
  scene.model.materials = {material};
  scene.model.fixed = {"clamp"};
  scene.model.loads.gravity = {0.0, -gravity, 0.0};
  scene.solver.type = type;
  return scene;
}

/// Mean y displacement of the tip group's nodes.
double tip_deflection(const Mesh& mesh, const Model& model, const std::vector<double>& u) {
  const Group* tip = mesh.group("tip");
  if (tip == nullptr || tip->nodes.empty()) return NAN;
  double sum = 0.0;
  for (const int node : tip->nodes) sum += u[static_cast<std::size_t>(node) * model.dim() + 1];
  return sum / static_cast<double>(tip->nodes.size());
}

/// Statistics of the steps after the first (warm-up) one of a dynamic run.
struct StepFigures {
  int steps = 0;  // counted steps
  double step_ms_mean = 0, step_ms_median = 0;
  double assembly_ms = 0, solve_ms = 0, rest_ms = 0;  // per counted step
  double linear_iterations = 0;                       // per counted step
  double first_step_ms = 0;                           // the warm-up step
};

/// Runs `steps` + 1 implicit steps and returns the figures of the last `steps`.
StepFigures run_implicit(const Model& model, const Assembler& assembler, const Scene& scene, State& state) {
  auto linear = make_linear_solver(scene.solver.linear);
  SolveStatistics statistics;
  Integration run{model, assembler, *linear, scene.solver, statistics};
  SolveStatistics warm;  // statistics after the warm-up step
  const StepObserver observer = [&](const State& s) {
    if (s.step == 1) warm = statistics;
    return false;
  };
  solve_implicit(run, state, observer);
  StepFigures f;
  const std::vector<double> counted(statistics.step_ms.listed().begin() + 1, statistics.step_ms.listed().end());
  f.steps = static_cast<int>(counted.size());
  f.first_step_ms = statistics.step_ms[0];
  f.step_ms_mean = mean(counted);
  f.step_ms_median = median(counted);
  f.assembly_ms = 1e3 * (statistics.assembly_seconds - warm.assembly_seconds) / f.steps;
  f.solve_ms = 1e3 * (statistics.solve_seconds - warm.solve_seconds) / f.steps;
  f.rest_ms = f.step_ms_mean - f.assembly_ms - f.solve_ms;
  f.linear_iterations = static_cast<double>(statistics.linear_iterations - warm.linear_iterations) / f.steps;
  return f;
}

/// The peak resident memory of this process so far, MiB.
double peak_resident_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // KiB on Linux
}

/// Median seconds of `repetitions` calls of `work`.
double time_median(int repetitions, const std::function<void()>& work) {
  std::vector<double> samples;
  for (int r = 0; r < repetitions; ++r) {
    const auto start = Clock::now();
    work();
    samples.push_back(since(start));
  }
  return median(samples);
}

// --- 1. CalculiX comparison -----------------------------------------------------

struct CcxSettings {
  std::array<int, 3> cells;
  int increments;
  int repetitions;
};
// The cantilever of the CalculiX comparison: 15,360 tets, 20 load steps, its tip
// sagging by 17 % of its length.
constexpr CcxSettings kCcxFull{{40, 8, 8}, 20, 3};
constexpr CcxSettings kCcxQuick{{20, 4, 4}, 10, 3};
constexpr std::array<double, 3> kCcxSize{5.0, 1.0, 1.0};
constexpr double kCcxYoung = 1.0e7;
constexpr double kCcxGravity = 9.81;        // m/s^2
constexpr double kAgreementFailure = 1e-4;  // beyond this the bench fails (exit 1)

bool run_ccx_comparison(const Options& options, Json& json, std::vector<Target>& targets) {
  const CcxSettings settings = options.quick ? kCcxQuick : kCcxFull;
  const Threads scope(options.threads > 0 ? options.threads : omp_get_max_threads());
  const int threads = omp_get_max_threads();
  std::printf("\n== 1. Static StVK cantilever: tensormass vs CalculiX (NLGEOM) ==\n");
  const Mesh mesh = beam_mesh(3, "tet6", settings.cells, kCcxSize);
  Scene scene = cantilever("stvk", kCcxYoung, kCcxGravity, SolverType::static_newton);
  scene.solver.load_steps = settings.increments;
  scene.solver.tolerance = 1e-10;
  scene.solver.max_iterations = 50;
  scene.solver.linear.type = LinearSolverType::cholmod;
  std::printf("beam %d x %d x %d cubes x 6 tets (tet6, Kuhn) = %d tet4, %d nodes; L x H x W = %g x %g x %g m\n",
              settings.cells[0], settings.cells[1], settings.cells[2], mesh.cell_count(), mesh.node_count(),
              kCcxSize[0], kCcxSize[1], kCcxSize[2]);
  std::printf(
      "StVK E = %g Pa, nu = %g, rho = %g kg/m^3, gravity %g m/s^2 (-y), clamped at x = 0; %d load steps / "
      "fixed increments; tensormass Newton tol 1e-10 (relative residual), CHOLMOD; ccx C3D4 NLGEOM, "
      "*STATIC DIRECT, tight *CONTROLS; %d thread(s) each (OMP_NUM_THREADS=%d for ccx)%s\n",
      kCcxYoung, kPoisson, kDensity, kCcxGravity, settings.increments, threads, threads,
      options.threads > 0 ? "" : ", tensormass with its default settings");
  json["tets"] = mesh.cell_count();
  json["nodes"] = mesh.node_count();
  json["increments"] = settings.increments;
  json["threads"] = threads;
  json["gravity"] = figure(kCcxGravity);
  json["young"] = figure(kCcxYoung);

  const std::string ccx = find_calculix(options.ccx);
  if (ccx.empty()) {
    std::printf("SKIPPED: CalculiX (%s) not found (install calculix-ccx, or give --ccx PATH or TENSORMASS_CCX)\n",
                options.ccx.empty() ? "ccx" : options.ccx.c_str());
    json["skipped"] = "ccx not found";
    return true;
  }
  CalculixOptions ccx_options;
  ccx_options.executable = ccx;
  ccx_options.increments = settings.increments;
  ccx_options.threads = threads;
  ccx_options.keep_directory = options.keep_ccx;

  std::vector<double> tm_setup, tm_solve, tm_total, tm_assembly, tm_linear, ccx_wall, ccx_reported;
  int newton = 0, ccx_iterations = 0;
  std::vector<double> u_tm, u_ccx;
  for (int rep = 0; rep < settings.repetitions; ++rep) {
    {
      const auto start = Clock::now();
      Model model(mesh, scene.model);
      Assembler assembler(model);
      auto linear = make_linear_solver(scene.solver.linear);
      const double setup = since(start);
      SolveStatistics statistics;
      Integration run{model, assembler, *linear, scene.solver, statistics};
      State state;
      const auto solve_start = Clock::now();
      solve_static(run, state, nullptr);
      const double solve = since(solve_start);
      tm_setup.push_back(setup);
      tm_solve.push_back(solve);
      tm_total.push_back(setup + solve);
      tm_assembly.push_back(statistics.assembly_seconds);
      tm_linear.push_back(statistics.solve_seconds);
      newton = statistics.newton_iterations;
      u_tm = state.displacement;
    }
    const CalculixResult result = run_calculix(mesh, scene, ccx_options);
    if (options.keep_ccx) std::printf("ccx work directory: %s\n", result.directory.c_str());
    ccx_wall.push_back(result.wall_seconds);
    ccx_reported.push_back(result.reported_seconds);
    ccx_iterations = result.iterations;
    u_ccx = result.displacement;
  }

  // Agreement: max nodal |u_tm - u_ccx| / max nodal |u_ccx| (3D: dof = node * 3 + a).
  double difference = 0.0, largest = 0.0;
  for (int node = 0; node < mesh.node_count(); ++node) {
    double d2 = 0.0, u2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double tm = u_tm[static_cast<std::size_t>(node) * 3 + a],
                   cx = u_ccx[static_cast<std::size_t>(node) * 3 + a];
      d2 += (tm - cx) * (tm - cx);
      u2 += cx * cx;
    }
    difference = std::max(difference, std::sqrt(d2));
    largest = std::max(largest, std::sqrt(u2));
  }
  const double agreement = largest > 0.0 ? difference / largest : difference;
  double tip = 0.0;
  if (const Group* group = mesh.group("tip"))
    for (const int node : group->nodes) tip += u_ccx[static_cast<std::size_t>(node) * 3 + 1] / group->nodes.size();
  const double ratio = median(ccx_wall) / median(tm_total);
  const double ratio_solve = median(ccx_wall) / median(tm_solve);

  const std::string heading = "median of " + std::to_string(settings.repetitions) + " runs";
  std::printf("\n%-34s %12s %12s\n", heading.c_str(), "tensormass", "ccx");
  std::printf("%-34s %12.3f %12.3f\n", "wall time (s)", median(tm_total), median(ccx_wall));
  std::printf("%-34s %12.3f %12s\n", "  model + assembler setup (s)", median(tm_setup), "");
  std::printf("%-34s %12.3f %12.3f\n", "  solve (s) / ccx's own total (s)", median(tm_solve), median(ccx_reported));
  std::printf("%-34s %12.3f %12s\n", "    assembly (s)", median(tm_assembly), "");
  std::printf("%-34s %12.3f %12s\n", "    factorise + solve (s)", median(tm_linear), "");
  std::printf("%-34s %12d %12d\n", "Newton iterations (all steps)", newton, ccx_iterations);
  std::printf("tip deflection %.4f m = %.1f %% of L (ccx); max |u| %.4f m\n", -tip, -100.0 * tip / kCcxSize[0],
              largest);
  std::printf("agreement: max nodal |u_tm - u_ccx| / max |u_ccx| = %.2e (ccx prints 7 significant digits)\n",
              agreement);
  std::printf("time ratio ccx / tensormass = %.2f (setup + solve), %.2f (solve only)\n", ratio, ratio_solve);

  json["tip_deflection"] = figure(-tip);
  json["max_displacement"] = figure(largest);
  json["agreement"] = figure(agreement);
  json["tensormass_total_s"] = figure(median(tm_total));
  json["tensormass_setup_s"] = figure(median(tm_setup));
  json["tensormass_solve_s"] = figure(median(tm_solve));
  json["tensormass_assembly_s"] = figure(median(tm_assembly));
  json["tensormass_linear_s"] = figure(median(tm_linear));
  json["tensormass_newton_iterations"] = newton;
  json["ccx_wall_s"] = figure(median(ccx_wall));
  json["ccx_reported_s"] = figure(median(ccx_reported));
  json["ccx_iterations"] = ccx_iterations;
  json["ratio_ccx_over_tensormass"] = figure(ratio);
  json["ratio_ccx_over_tensormass_solve_only"] = figure(ratio_solve);
  json["tensormass_total_samples_s"] = figures(tm_total);
  json["ccx_wall_samples_s"] = figures(ccx_wall);

  targets.push_back(
      {"ccx wall / tensormass wall, " + std::to_string(mesh.cell_count()) + " tets", ratio, ">=", 5.0, true});
  targets.push_back({"displacement agreement with ccx (relative)", agreement, "<=", 1e-5, true});
  if (!(agreement <= kAgreementFailure)) {
    std::fprintf(stderr, "tensormass bench runtime: tensormass and CalculiX disagree (%.3e > %.0e)\n", agreement,
                 kAgreementFailure);
    return false;
  }
  return true;
}

// --- 2. Default threads against one ------------------------------------------------

struct ThreadRun {
  double seconds = 0, assembly = 0, solve = 0;
};

/// One whole implicit run (steps, not setup) with `threads` OpenMP threads.
ThreadRun time_implicit_run(const Model& model, const Assembler& assembler, const Scene& scene, int threads) {
  const Threads scope(threads);
  auto linear = make_linear_solver(scene.solver.linear);
  SolveStatistics statistics;
  Integration run{model, assembler, *linear, scene.solver, statistics};
  State state;
  const auto start = Clock::now();
  solve_implicit(run, state, nullptr);
  return {since(start), statistics.assembly_seconds, statistics.solve_seconds};
}

constexpr double kThreadsYoung = 1.0e7;

bool run_thread_defaults(const Options& options, Json& json, std::vector<Target>& targets) {
  constexpr std::array<int, 3> kCells{30, 8, 6};
  const int steps = options.quick ? 10 : 100, repetitions = 3;
  const int defaults = omp_get_max_threads();
  std::printf("\n== 2. Default threads (%d) against one: implicit StVK beam ==\n", defaults);
  const Mesh mesh = beam_mesh(3, "tet6", kCells, {3.75, 1.0, 0.75});
  Scene scene = cantilever("stvk", kThreadsYoung, 9.81, SolverType::implicit_euler);
  scene.solver.dt = 0.01;
  scene.solver.steps = steps;
  std::printf("%d tet4, %d steps of 0.01 s, default solver settings (CHOLMOD); runs alternate, median of %d\n",
              mesh.cell_count(), steps, repetitions);
  const Model model(mesh, scene.model);
  const Assembler assembler(model);
  std::vector<ThreadRun> runs[2];
  const int counts[2] = {1, defaults};
  for (int rep = 0; rep < repetitions; ++rep)
    for (int k = 0; k < 2; ++k) runs[k].push_back(time_implicit_run(model, assembler, scene, counts[k]));
  std::printf("%8s %10s %12s %12s %12s\n", "threads", "run (s)", "step (ms)", "assembly (s)", "solve (s)");
  double medians[2];
  for (int k = 0; k < 2; ++k) {
    std::vector<double> seconds, assembly, solve;
    for (const ThreadRun& r : runs[k]) {
      seconds.push_back(r.seconds);
      assembly.push_back(r.assembly);
      solve.push_back(r.solve);
    }
    medians[k] = median(seconds);
    std::printf("%8d %10.3f %12.2f %12.3f %12.3f\n", counts[k], medians[k], 1e3 * medians[k] / steps, median(assembly),
                median(solve));
    json[k == 0 ? "one_thread" : "default_threads"] = {{"threads", counts[k]},
                                                       {"run_s", figure(medians[k])},
                                                       {"assembly_s", figure(median(assembly))},
                                                       {"solve_s", figure(median(solve))},
                                                       {"run_samples_s", figures(seconds)}};
  }
  const double ratio = medians[1] / medians[0];
  std::printf("default / one thread = %.2f (target <= 1.0, goal 0.65 on 2 cores)\n", ratio);
  json["tets"] = mesh.cell_count();
  json["steps"] = steps;
  json["ratio_default_over_one"] = figure(ratio);
  targets.push_back({"default threads / one thread, " + std::to_string(mesh.cell_count()) + "-tet implicit run", ratio,
                     "<=", 1.0, true});
  return true;
}

// --- 3. Implicit steps ------------------------------------------------------------

struct ImplicitCase {
  const char* label;
  std::array<int, 3> cells;
  int cg_steps;       // counted steps per run
  int cholmod_steps;  // (a 100k-tet factorisation takes seconds with reference BLAS)
  int repetitions;
};
constexpr ImplicitCase kImplicitFull[] = {
    {"1k", {14, 4, 3}, 20, 20, 5}, {"10k", {35, 8, 6}, 10, 10, 5}, {"100k", {70, 16, 15}, 3, 1, 3}};
// --scaling adds a million tets, CG only: one CHOLMOD factorisation of it
// would take minutes and several GiB (the 100k row's scales as n^2).
constexpr ImplicitCase kImplicitScaling[] = {{"1k", {14, 4, 3}, 20, 20, 5},
                                             {"10k", {35, 8, 6}, 10, 10, 5},
                                             {"100k", {70, 16, 15}, 3, 1, 3},
                                             {"1M", {150, 34, 33}, 2, 0, 1}};
constexpr ImplicitCase kImplicitQuick[] = {{"10k", {35, 8, 6}, 3, 3, 3}};
constexpr double kImplicitYoung = 1.0e6;
constexpr double kImplicitDt = 0.01;
constexpr double kCgTolerance = 1e-8;

bool run_implicit_steps(const Options& options, Json& json, std::vector<Target>& targets) {
  std::printf("\n== 3. Implicit Euler steps, StVK tet4 beams (tet6 cut), 1 Newton iteration per step ==\n");
  std::printf(
      "E = %g Pa, nu = %g, rho = %g, gravity 9.81 (-y), dt = %g s, clamped; CG: Jacobi, tolerance %g, "
      "warm-started; one uncounted warm-up step per run\n",
      kImplicitYoung, kPoisson, kDensity, kImplicitDt, kCgTolerance);
  std::printf(
      "reference = one assembly (gradient + Hessian) + N_cg x one K.multiply (medians), timed in the same "
      "process right after each run, at its final state; ratio = median step / reference\n\n");
  std::printf("%-5s %7s %7s %-8s %3s %9s %9s %9s %9s %9s %7s %9s %9s %7s %9s %6s %7s\n", "mesh", "tets", "dofs",
              "solver", "thr", "step ms", "median", "assembly", "solve", "rest", "N_lin", "asm ref", "spmv ms", "ratio",
              "1st step", "GB/s", "RSS MB");
  const int defaults = omp_get_max_threads();
  const std::vector<int> thread_counts =
      options.quick || defaults == 1 ? std::vector<int>{defaults} : std::vector<int>{1, defaults};
  const ImplicitCase* begin = options.quick     ? std::begin(kImplicitQuick)
                              : options.scaling ? std::begin(kImplicitScaling)
                                                : std::begin(kImplicitFull);
  const ImplicitCase* end = options.quick     ? std::end(kImplicitQuick)
                            : options.scaling ? std::end(kImplicitScaling)
                                              : std::end(kImplicitFull);
  for (const ImplicitCase* c = begin; c != end; ++c) {
    const std::array<double, 3> size{double(c->cells[0]) / c->cells[1], 1.0, double(c->cells[2]) / c->cells[1]};
    const Mesh mesh = beam_mesh(3, "tet6", c->cells, size);
    for (const std::string solver : {"cholmod", "cg"})
      for (const int threads : thread_counts) {
        if (solver == "cholmod" && c->cholmod_steps == 0) continue;
        Threads scope(threads);
        Scene scene = cantilever("stvk", kImplicitYoung, 9.81, SolverType::implicit_euler);
        scene.solver.dt = kImplicitDt;
        const int steps = solver == "cg" ? c->cg_steps : c->cholmod_steps;
        scene.solver.steps = steps + 1;
        scene.solver.newton_iterations = 1;
        scene.solver.linear.type = solver == "cg" ? LinearSolverType::cg : LinearSolverType::cholmod;
        scene.solver.linear.tolerance = kCgTolerance;
        const Model model(mesh, scene.model);
        const Assembler assembler(model);
        std::vector<double> step_mean, step_median, assembly, solve, rest, iterations, first, asm_ref, spmv, ratio;
        for (int rep = 0; rep < c->repetitions; ++rep) {
          State state;
          const StepFigures f = run_implicit(model, assembler, scene, state);
          // The reference, at the final state, same threads.
          SparseMatrix K = assembler.pattern();
          std::vector<double> g(model.dof_count());
          const double t_assembly =
              time_median(c->repetitions >= 3 ? 5 : 3, [&] { assembler.assemble(state.displacement, g, &K); });
          std::vector<double> x(K.rows), y(K.rows);
          for (int i = 0; i < K.rows; ++i) x[i] = 1.0 + 1e-3 * (i % 7);
          constexpr int kBatch = 20;
          const double t_spmv = time_median(5,
                                            [&] {
                                              for (int b = 0; b < kBatch; ++b) K.multiply(x, y);
                                            }) /
                                kBatch;
          const double reference_ms = 1e3 * (t_assembly + f.linear_iterations * t_spmv);
          step_mean.push_back(f.step_ms_mean);
          step_median.push_back(f.step_ms_median);
          assembly.push_back(f.assembly_ms);
          solve.push_back(f.solve_ms);
          rest.push_back(f.rest_ms);
          iterations.push_back(f.linear_iterations);
          first.push_back(f.first_step_ms);
          asm_ref.push_back(1e3 * t_assembly);
          spmv.push_back(1e3 * t_spmv);
          ratio.push_back(f.step_ms_median / reference_ms);
        }
        const bool cg = solver == "cg";
        char ratio_text[32];
        std::snprintf(ratio_text, sizeof ratio_text, "%.2f", median(ratio));
        // Bytes one K.multiply moves at least: values and columns, row starts, x and y.
        const SparseMatrix& pattern = assembler.pattern();
        const double spmv_bytes = 12.0 * pattern.nonzeros() + 20.0 * pattern.rows;
        const double bandwidth = spmv_bytes / (1e-3 * median(spmv)) / 1e9;
        const double rss_mb = peak_resident_mb();
        std::printf("%-5s %7d %7d %-8s %3d %9.2f %9.2f %9.2f %9.2f %9.2f %7.1f %9.2f %9.3f %7s %9.1f %6.1f %7.0f\n",
                    c->label, mesh.cell_count(), model.free_dof_count(), solver.c_str(), threads, median(step_mean),
                    median(step_median), median(assembly), median(solve), median(rest), median(iterations),
                    median(asm_ref), median(spmv), cg ? ratio_text : "-", median(first), bandwidth, rss_mb);
        std::fflush(stdout);
        Json row = {{"mesh", c->label},
                    {"tets", mesh.cell_count()},
                    {"free_dofs", model.free_dof_count()},
                    {"nonzeros", assembler.pattern().nonzeros()},
                    {"solver", solver},
                    {"threads", threads},
                    {"steps", steps},
                    {"repetitions", c->repetitions}};
        row["step_ms"] = figure(median(step_mean));
        row["step_ms_median"] = figure(median(step_median));
        row["assembly_ms"] = figure(median(assembly));
        row["solve_ms"] = figure(median(solve));
        row["rest_ms"] = figure(median(rest));
        row["linear_iterations_per_step"] = figure(median(iterations));
        row["first_step_ms"] = figure(median(first));
        row["reference_assembly_ms"] = figure(median(asm_ref));
        row["spmv_ms"] = figure(median(spmv));
        row["spmv_bytes"] = figure(spmv_bytes);
        row["spmv_gb_per_s"] = figure(bandwidth);
        row["peak_rss_mb"] = figure(rss_mb);
        if (cg) row["ratio_step_over_reference"] = figure(median(ratio));
        json.push_back(row);
        if (cg && threads == 1 && std::string(c->label) == "10k")
          targets.push_back(
              {"CG step / (assembly + N_cg spmv), " + std::to_string(mesh.cell_count()) + " tets, 1 thread",
               median(ratio), "<=", 1.3, true});
        if (threads == defaults && std::string(c->label) == "100k")
          targets.push_back({solver + " step (ms), " + std::to_string(mesh.cell_count()) + " tets, default threads",
                             median(step_mean), "<=", 100.0, true});
      }
  }
  std::printf(
      "(step ms: mean of the counted steps, median: their median; assembly/solve/rest: per counted step, "
      "rest = mean step - assembly - solve; N_lin: linear iterations per step; ratio: CG only; GB/s: the "
      "bytes one K.multiply must move (12 per non-zero, 20 per row) over its time; RSS MB: the process's peak "
      "resident memory so far (rows run in increasing size); all columns: median over the runs)\n");
  return true;
}

// --- 4. The origin report's 600-quad beam ------------------------------------------

constexpr double kQuadYoung = 1.0e7;  // as examples/beam

/// Figures of every counted step of a dynamic run (after one warm-up step).
struct LawRun {
  std::string law;
  std::unique_ptr<Model> model;
  std::unique_ptr<Assembler> assembler;
  Scene scene;
  std::vector<double> mean_ms, median_ms, assembly_ms, solve_ms;
  double tip = 0;
};

/// Runs Hooke and StVK alternately `repetitions` times with `integrator`.
void run_laws(const Mesh& mesh, std::vector<LawRun>& runs, int repetitions,
              const std::function<StepFigures(LawRun&, State&)>& integrator) {
  for (int rep = 0; rep < repetitions; ++rep)
    for (LawRun& r : runs) {
      State state;
      const StepFigures f = integrator(r, state);
      r.mean_ms.push_back(f.step_ms_mean);
      r.median_ms.push_back(f.step_ms_median);
      r.assembly_ms.push_back(f.assembly_ms);
      r.solve_ms.push_back(f.solve_ms);
      r.tip = tip_deflection(mesh, *r.model, state.displacement);
    }
}

std::vector<LawRun> make_law_runs(const Mesh& mesh, const std::function<void(Scene&)>& configure) {
  std::vector<LawRun> runs(2);
  runs[0].law = "hooke";
  runs[1].law = "stvk";
  for (LawRun& r : runs) {
    r.scene = cantilever(r.law, kQuadYoung, 9.81, SolverType::implicit_euler);
    configure(r.scene);
    r.model = std::make_unique<Model>(mesh, r.scene.model);
    r.assembler = std::make_unique<Assembler>(*r.model);
  }
  return runs;
}

/// Prints the rows of one integrator and returns its JSON; `ratio` gets stvk/hooke of the medians.
Json report_laws(const char* integrator, const std::vector<LawRun>& runs, double& ratio, double& ratio_mean) {
  std::printf("\n%-9s %-7s %11s %11s %12s %10s %14s   %s\n", "", "law", "mean ms", "median ms", "assembly ms",
              "solve ms", "tip defl. (m)", "origin report (mean ms)");
  const char* origin[2] = {"0.102", "16.273"};
  Json rows = Json::array();
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const LawRun& r = runs[i];
    std::printf("%-9s %-7s %11.4f %11.4f %12.4f %10.4f %14.4f   %s\n", i == 0 ? integrator : "", r.law.c_str(),
                median(r.mean_ms), median(r.median_ms), median(r.assembly_ms), median(r.solve_ms), -r.tip, origin[i]);
    rows.push_back({{"law", r.law},
                    {"step_ms_mean", figure(median(r.mean_ms))},
                    {"step_ms_median", figure(median(r.median_ms))},
                    {"assembly_ms", figure(median(r.assembly_ms))},
                    {"solve_ms", figure(median(r.solve_ms))},
                    {"tip_deflection", figure(-r.tip)},
                    {"step_ms_mean_samples", figures(r.mean_ms)},
                    {"step_ms_median_samples", figures(r.median_ms)}});
  }
  ratio = median(runs[1].median_ms) / median(runs[0].median_ms);
  ratio_mean = median(runs[1].mean_ms) / median(runs[0].mean_ms);
  const double ratio_assembly = median(runs[1].assembly_ms) / median(runs[0].assembly_ms);
  std::printf("%-9s stvk / hooke: %.2f (median ms per step), %.2f (mean), assembly alone %.2f; origin report %.0fx\n",
              "", ratio, ratio_mean, ratio_assembly, 16.273 / 0.102);
  return {{"laws", rows},
          {"ratio_stvk_over_hooke", figure(ratio)},
          {"ratio_stvk_over_hooke_mean", figure(ratio_mean)},
          {"ratio_assembly", figure(ratio_assembly)}};
}

bool run_quad_beam(const Options& options, Json& json, std::vector<Target>& targets) {
  const int steps = options.quick ? 20 : 100;
  const int explicit_steps = options.quick ? 200 : 1000;
  const int repetitions = options.quick ? 3 : 5;
  std::printf("\n== 4. The origin report's 2D beam: 60 x 10 quad4 (600 elements), one core ==\n");
  const Mesh mesh = beam_mesh(2, "quad4", {60, 10, 1}, {6.0, 1.0, 1.0});
  Threads scope(1);
  std::printf(
      "L x H = 6 x 1 m, plane strain, E = %g Pa, nu = %g, rho = %g, gravity 9.81 (-y), clamped at x = 0; "
      "median of %d runs, Hooke and StVK alternating; each run has one uncounted warm-up step\n",
      kQuadYoung, kPoisson, kDensity, repetitions);
  std::printf("implicit: backward Euler, dt = 0.01 s, %d counted steps, 1 Newton iteration per step, CHOLMOD\n", steps);

  std::vector<LawRun> implicit_runs = make_law_runs(mesh, [&](Scene& scene) {
    scene.solver.type = SolverType::implicit_euler;
    scene.solver.dt = 0.01;
    scene.solver.steps = steps + 1;
    scene.solver.newton_iterations = 1;
    scene.solver.linear.type = LinearSolverType::cholmod;
  });
  run_laws(mesh, implicit_runs, repetitions,
           [](LawRun& r, State& state) { return run_implicit(*r.model, *r.assembler, r.scene, state); });

  // Explicit (symplectic Euler, lumped mass): no linear solve, so the law's
  // cost shows fully. dt = half the estimated stable step at rest.
  const double stable = estimate_stable_time_step(*implicit_runs[0].model, *implicit_runs[0].assembler);
  const double explicit_dt = 0.5 * stable;
  std::printf("explicit: symplectic Euler, dt = %.3g s (half the estimated stable %.3g s), %d counted steps\n",
              explicit_dt, stable, explicit_steps);
  std::vector<LawRun> explicit_runs = make_law_runs(mesh, [&](Scene& scene) {
    scene.solver.type = SolverType::explicit_euler;
    scene.solver.dt = explicit_dt;
    scene.solver.steps = explicit_steps + 1;
  });
  run_laws(mesh, explicit_runs, repetitions, [](LawRun& r, State& state) {
    auto linear = make_linear_solver(r.scene.solver.linear);
    SolveStatistics statistics;
    Integration run{*r.model, *r.assembler, *linear, r.scene.solver, statistics};
    SolveStatistics warm;
    solve_explicit(run, state, [&](const State& s) {
      if (s.step == 1) warm = statistics;
      return false;
    });
    StepFigures f;
    const std::vector<double> counted(statistics.step_ms.listed().begin() + 1, statistics.step_ms.listed().end());
    f.steps = static_cast<int>(counted.size());
    f.step_ms_mean = mean(counted);
    f.step_ms_median = median(counted);
    f.assembly_ms = 1e3 * (statistics.assembly_seconds - warm.assembly_seconds) / f.steps;
    return f;
  });

  double ratio = 0, ratio_mean = 0, explicit_ratio = 0, explicit_ratio_mean = 0;
  Json implicit_json = report_laws("implicit", implicit_runs, ratio, ratio_mean);
  Json explicit_json = report_laws("explicit", explicit_runs, explicit_ratio, explicit_ratio_mean);
  implicit_json["dt"] = figure(0.01);
  implicit_json["steps"] = steps;
  explicit_json["dt"] = figure(explicit_dt);
  explicit_json["steps"] = explicit_steps;
  json = {{"elements", mesh.cell_count()},
          {"repetitions", repetitions},
          {"young", figure(kQuadYoung)},
          {"implicit", implicit_json},
          {"explicit", explicit_json}};
  targets.push_back({"600-quad beam, implicit: stvk / hooke median ms per step", ratio, "<=", 2.5, true});
  return true;
}

// --- 5. Batched kernels in the assembly --------------------------------------------

struct BatchCase {
  const char* label;
  const char* law;
  const char* cut;  // beam cut: tet6 (6 tets per cube) or hex8
  std::array<int, 3> cells;
};
constexpr BatchCase kBatchCases[] = {{"stvk tet4", "stvk", "tet6", {40, 8, 8}},
                                     {"neohookean tet4", "neohookean", "tet6", {40, 8, 8}},
                                     {"stvk hex8", "stvk", "hex8", {40, 8, 8}}};

/// Median ms of assemblies batched and per element, alternated: `tangent`
/// true for forces and tangent (implicit and static steps), false for the
/// forces alone (explicit steps). Two assemblers, each keeping its plan of
/// the kernel cells (KernelPlan): toggling one would plan it again each time.
std::array<double, 2> time_batched_assembly(const Assembler& per_element, const Assembler& batched,
                                            const std::vector<double>& u, bool tangent, int repetitions) {
  std::vector<double> g(u.size());
  SparseMatrix K = batched.pattern();
  std::vector<double> samples[2];  // per element, batched
  for (int rep = 0; rep < repetitions + 1; ++rep)
    for (int b = 0; b < 2; ++b) {
      const Assembler& assembler = b == 1 ? batched : per_element;
      const auto start = Clock::now();
      assembler.assemble(u, g, tangent ? &K : nullptr);
      if (rep > 0) samples[b].push_back(1e3 * since(start));  // the first is a warm-up
    }
  return {median(samples[0]), median(samples[1])};
}

bool run_batched_assembly(const Options& options, Json& json, std::vector<Target>& targets) {
  const int repetitions = options.quick ? 5 : 21;
  const int defaults = omp_get_max_threads();
  std::printf("\n== 5. Batched kernels in the assembly: batched vs per element ==\n");
  std::printf(
      "one assembly of u = a small wave (values do not change the time); runs alternate, median of %d; "
      "hex8 has no batched kernels (the per-element ones are faster); neo-Hookean's log runs on all lanes "
      "through libmvec\n",
      repetitions);
  std::printf("%-16s %6s %7s | %-26s | %-26s\n", "", "", "", "forces + tangent (ms)", "forces alone (ms)");
  std::printf("%-16s %6s %7s | %9s %9s %6s | %9s %9s %6s\n", "case", "cells", "threads", "per elem", "batched", "ratio",
              "per elem", "batched", "ratio");
  for (const BatchCase& c : kBatchCases) {
    std::array<int, 3> cells = c.cells;
    if (options.quick) cells = {10, 4, 4};
    const Mesh mesh = beam_mesh(3, c.cut, cells, {0.1 * cells[0], 0.1 * cells[1], 0.1 * cells[2]});
    const Scene scene = cantilever(c.law, 1.0e6, 9.81, SolverType::implicit_euler);
    const Model model(mesh, scene.model);
    Assembler per_element(model), batched(model);
    per_element.set_batched(false);
    std::vector<double> u(model.dof_count());
    for (std::size_t i = 0; i < u.size(); ++i) u[i] = 1e-3 * std::sin(0.7 * static_cast<double>(i));
    for (const int threads : {1, defaults}) {
      const Threads scope(threads);
      const auto full = time_batched_assembly(per_element, batched, u, true, repetitions);
      const auto forces = time_batched_assembly(per_element, batched, u, false, repetitions);
      std::printf("%-16s %6d %7d | %9.3f %9.3f %6.2f | %9.3f %9.3f %6.2f\n", c.label, model.cell_count(), threads,
                  full[0], full[1], full[1] / full[0], forces[0], forces[1], forces[1] / forces[0]);
      json.push_back({{"case", c.label},
                      {"cells", model.cell_count()},
                      {"threads", threads},
                      {"tangent_per_element_ms", figure(full[0])},
                      {"tangent_batched_ms", figure(full[1])},
                      {"forces_per_element_ms", figure(forces[0])},
                      {"forces_batched_ms", figure(forces[1])}});
      if (threads == defaults && std::string(c.label) == "stvk tet4") {
        targets.push_back(
            {"batched / per-element assembly, forces + tangent, StVK tet4", full[1] / full[0], "<=", 1.0, true});
        targets.push_back(
            {"batched / per-element assembly, forces alone, StVK tet4", forces[1] / forces[0], "<=", 1.0, true});
      }
    }
  }
  return true;
}

// --- 6. The tangent product by node blocks -----------------------------------

/// Largest |a - b| over the largest |baseline|.
double relative_difference(const std::vector<double>& a, const std::vector<double>& baseline) {
  double worst = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    worst = std::max(worst, std::abs(a[i] - baseline[i]));
    scale = std::max(scale, std::abs(baseline[i]));
  }
  return worst / std::max(scale, 1e-300);
}

/// Median ms of K x by rows (column indices, the baseline) and by node
/// blocks (SparseMatrix::multiply), alternated; `difference`: their largest
/// difference over the largest entry.
std::array<double, 2> time_products(const SparseMatrix& K, int repetitions, double& difference) {
  std::vector<double> x(K.rows), by_rows(K.rows), by_blocks(K.rows);
  for (int i = 0; i < K.rows; ++i) x[i] = std::sin(0.37 * i);
  std::vector<double> samples[2];
  for (int rep = 0; rep < repetitions + 1; ++rep) {
    auto start = Clock::now();
    K.multiply_by_rows(x, by_rows);
    if (rep > 0) samples[0].push_back(1e3 * since(start));  // the first is a warm-up
    start = Clock::now();
    K.multiply(x, by_blocks);
    if (rep > 0) samples[1].push_back(1e3 * since(start));
  }
  difference = relative_difference(by_blocks, by_rows);
  return {median(samples[0]), median(samples[1])};
}

bool run_block_products(const Options& options, Json& json, std::vector<Target>& targets) {
  const int repetitions = options.quick ? 5 : 41;
  const int defaults = omp_get_max_threads();
  std::printf("\n== 6. The tangent product K x: by node blocks (the default) vs row by row ==\n");
  std::printf(
      "StVK tet6 beams, the tangent at rest; runs alternate, median of %d; GB/s: 12 bytes per non-zero and 20 per "
      "row over the row-by-row time\n",
      repetitions);
  std::printf("%-8s %9s %10s %7s | %9s %9s %6s %6s %9s\n", "mesh", "rows", "non-zeros", "threads", "by rows", "blocks",
              "ratio", "GB/s", "rel. diff");
  bool agree = true;
  const std::vector<std::array<int, 3>> sizes =
      options.quick ? std::vector<std::array<int, 3>>{{10, 4, 4}}
                    : std::vector<std::array<int, 3>>{{28, 6, 10}, {70, 12, 20}};  // 10k and 100k tets
  for (const auto& cells : sizes) {
    const Mesh mesh = beam_mesh(3, "tet6", cells, {0.1 * cells[0], 0.1 * cells[1], 0.1 * cells[2]});
    const Scene scene = cantilever("stvk", 1.0e6, 9.81, SolverType::implicit_euler);
    const Model model(mesh, scene.model);
    const Assembler assembler(model);
    std::vector<double> u(model.dof_count(), 0.0), g(model.dof_count());
    SparseMatrix K = assembler.pattern();
    assembler.assemble(u, g, &K);
    for (const int threads : {1, defaults}) {
      const Threads scope(threads);
      double difference = 0.0;
      const auto t = time_products(K, repetitions, difference);
      agree = agree && difference <= 1e-13;
      const double gbs = (12.0 * K.nonzeros() + 20.0 * K.rows) / (t[0] * 1e-3) / 1e9;
      std::printf("%-8s %9d %10d %7d | %9.3f %9.3f %6.2f %6.1f %9.1e\n",
                  (std::to_string(model.cell_count() / 1000) + "k").c_str(), K.rows, K.nonzeros(), threads, t[0], t[1],
                  t[1] / t[0], gbs, difference);
      json.push_back({{"tets", model.cell_count()},
                      {"rows", K.rows},
                      {"nonzeros", K.nonzeros()},
                      {"threads", threads},
                      {"by_rows_ms", figure(t[0])},
                      {"by_blocks_ms", figure(t[1])},
                      {"relative_difference", figure(difference)}});
      if (threads == defaults && &cells == &sizes.back())
        targets.push_back({"K x by node blocks / by rows, largest beam", t[1] / t[0], "<=", 1.0, true});
    }
  }
  if (!agree) std::printf("FAILED: the block product differs from the row product by more than rounding\n");
  return agree;
}

// --- 6b. The folded linear part's product ------------------------------------

/// g = K_L u from the folded blocks with one sum per row of the blocks (D
/// chains of additions per node, against LinearPart::multiply's D x D
/// sums), parallel above the same node count. The baseline of
/// run_folded_products.
template <int D>
void folded_product_one_sum_per_row(const NodeGraph& graph, const double* blocks, const double* u, double* g) {
  const int nodes = graph.node_count();
#pragma omp parallel for schedule(static) if (nodes >= 1000)
  for (int node = 0; node < nodes; ++node) {
    double sum[D] = {};
    for (int k = graph.row_start[node]; k < graph.row_start[node + 1]; ++k) {
      const double* block = blocks + static_cast<std::size_t>(k) * D * D;
      const double* x = u + static_cast<std::size_t>(graph.columns[k]) * D;
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) sum[a] += block[a * D + b] * x[b];
    }
    for (int a = 0; a < D; ++a) g[static_cast<std::size_t>(node) * D + a] = sum[a];
  }
}

/// Median ms of the folded Hooke forces K_L u: one sum per row (the
/// baseline) and LinearPart::multiply, alternated; `difference`: their
/// largest difference over the largest entry.
std::array<double, 2> time_folded_products(const Model& model, const LinearPart& linear, int repetitions,
                                           double& difference) {
  const NodeGraph graph = make_node_graph(model);
  const std::vector<double> blocks = linear.saved().blocks;
  std::vector<double> u(model.dof_count()), baseline(u.size()), current(u.size());
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = 1e-3 * std::sin(0.37 * static_cast<double>(i));
  std::vector<double> samples[2];
  for (int rep = 0; rep < repetitions + 1; ++rep) {
    auto start = Clock::now();
    folded_product_one_sum_per_row<3>(graph, blocks.data(), u.data(), baseline.data());
    if (rep > 0) samples[0].push_back(1e3 * since(start));  // the first is a warm-up
    start = Clock::now();
    linear.multiply(u, current);
    if (rep > 0) samples[1].push_back(1e3 * since(start));
  }
  difference = relative_difference(current, baseline);
  return {median(samples[0]), median(samples[1])};
}

bool run_folded_products(const Options& options, Json& json, std::vector<Target>& targets) {
  const int repetitions = options.quick ? 5 : 101;
  const int defaults = omp_get_max_threads();
  std::printf("\n== 6b. Folded Hooke forces K_L u: D x D sums per node (the default) vs one sum per row ==\n");
  std::printf("Hooke tet6 beams; runs alternate, median of %d\n", repetitions);
  std::printf("%-8s %7s %7s | %9s %9s %6s %9s\n", "mesh", "nodes", "threads", "per row", "D x D", "ratio", "rel. diff");
  bool agree = true;
  const std::vector<std::array<int, 3>> sizes =
      options.quick ? std::vector<std::array<int, 3>>{{10, 4, 4}}
                    : std::vector<std::array<int, 3>>{{20, 10, 20}, {70, 12, 20}};  // 24k (indentation) and 100k tets
  for (const auto& cells : sizes) {
    const Mesh mesh = beam_mesh(3, "tet6", cells, {0.1 * cells[0], 0.1 * cells[1], 0.1 * cells[2]});
    const Scene scene = cantilever("hooke", 1.0e6, 9.81, SolverType::explicit_euler);
    const Model model(mesh, scene.model);
    const Assembler assembler(model);
    std::vector<double> zero(model.dof_count(), 0.0), g(model.dof_count());
    assembler.assemble(zero, g, nullptr);  // folds the cells
    for (const int threads : {1, defaults}) {
      const Threads scope(threads);
      double difference = 0.0;
      const auto t = time_folded_products(model, *assembler.linear_part(), repetitions, difference);
      agree = agree && difference <= 1e-13;
      std::printf("%-8s %7d %7d | %9.4f %9.4f %6.2f %9.1e\n", (std::to_string(model.cell_count() / 1000) + "k").c_str(),
                  mesh.node_count(), threads, t[0], t[1], t[1] / t[0], difference);
      json.push_back({{"tets", model.cell_count()},
                      {"nodes", mesh.node_count()},
                      {"threads", threads},
                      {"one_sum_per_row_ms", figure(t[0])},
                      {"d_by_d_sums_ms", figure(t[1])},
                      {"relative_difference", figure(difference)}});
      if (threads == defaults && &cells == &sizes.front())
        targets.push_back({"folded K_L u, D x D sums / one per row, 24k tets", t[1] / t[0], "<=", 1.0, true});
    }
  }
  if (!agree) std::printf("FAILED: the two folded products differ by more than rounding\n");
  return agree;
}

// --- 7. The tangent scatter by node blocks ------------------------------------

struct ScatterCase {
  const char* label;
  int dim;
  const char* cut;
  std::array<int, 3> cells;
};
constexpr ScatterCase kScatterCases[] = {{"stvk quad4", 2, "quad4", {60, 10, 1}},
                                         {"stvk tet4 10k", 3, "tet6", {28, 6, 10}},
                                         {"stvk tet4 100k", 3, "tet6", {70, 12, 20}},
                                         {"stvk hex8", 3, "hex8", {40, 8, 8}}};

/// Median ms of assemblies (forces + tangent) scattering by entries (the
/// baseline) and by node blocks, alternated; `same`: identical values.
std::array<double, 2> time_scatters(Assembler& assembler, const std::vector<double>& u, int repetitions, bool& same) {
  std::vector<double> g(u.size());
  SparseMatrix K[2] = {assembler.pattern(), assembler.pattern()};
  std::vector<double> samples[2];  // by entries, by blocks
  for (int rep = 0; rep < repetitions + 1; ++rep)
    for (int blocks = 0; blocks < 2; ++blocks) {
      assembler.set_scatter_by_blocks(blocks == 1);
      const auto start = Clock::now();
      assembler.assemble(u, g, &K[blocks]);
      if (rep > 0) samples[blocks].push_back(1e3 * since(start));  // the first is a warm-up
    }
  same = K[0].values == K[1].values;
  return {median(samples[0]), median(samples[1])};
}

bool run_scatter(const Options& options, Json& json, std::vector<Target>& targets) {
  const int repetitions = options.quick ? 5 : 21;
  const int defaults = omp_get_max_threads();
  std::printf("\n== 7. The tangent scatter: by node blocks (the default) vs one index per Hessian entry ==\n");
  std::printf(
      "one assembly (forces + tangent) of u = a small wave; runs alternate, median of %d; map: the scatter map's "
      "MiB\n",
      repetitions);
  std::printf("%-15s %7s %7s | %9s %9s %6s | %8s %8s\n", "case", "cells", "threads", "entries", "blocks", "ratio",
              "map MiB", "(entries)");
  bool agree = true;
  for (const ScatterCase& c : kScatterCases) {
    std::array<int, 3> cells = c.cells;
    if (options.quick) cells = c.dim == 2 ? std::array<int, 3>{20, 4, 1} : std::array<int, 3>{10, 4, 4};
    const Mesh mesh = beam_mesh(c.dim, c.cut, cells, {0.1 * cells[0], 0.1 * cells[1], 0.1 * cells[2]});
    const Scene scene = cantilever("stvk", 1.0e6, 9.81, SolverType::implicit_euler);
    const Model model(mesh, scene.model);
    Assembler assembler(model);
    const double block_mib = assembler.scatter_map_bytes() / 1048576.0;
    assembler.set_scatter_by_blocks(false);
    const double entry_mib = assembler.scatter_map_bytes() / 1048576.0;
    std::vector<double> u(model.dof_count());
    for (std::size_t i = 0; i < u.size(); ++i) u[i] = 1e-3 * std::sin(0.7 * static_cast<double>(i));
    for (const int threads : {1, defaults}) {
      const Threads scope(threads);
      bool same = false;
      const auto t = time_scatters(assembler, u, repetitions, same);
      agree = agree && same;
      std::printf("%-15s %7d %7d | %9.3f %9.3f %6.2f | %8.1f %8.1f\n", c.label, model.cell_count(), threads, t[0], t[1],
                  t[1] / t[0], block_mib, entry_mib);
      json.push_back({{"case", c.label},
                      {"cells", model.cell_count()},
                      {"threads", threads},
                      {"by_entries_ms", figure(t[0])},
                      {"by_blocks_ms", figure(t[1])},
                      {"identical", same},
                      {"map_mib_blocks", figure(block_mib)},
                      {"map_mib_entries", figure(entry_mib)}});
      if (threads == defaults && std::string(c.label) == "stvk tet4 100k")
        targets.push_back({"assembly, scatter by node blocks / by entries, 100k tets", t[1] / t[0], "<=", 1.0, true});
    }
  }
  if (!agree) std::printf("FAILED: the two scatters gave different tangents\n");
  return agree;
}

bool parse(const std::vector<std::string>& args, Options& options, int& exit_code) {
  auto value = [&](std::size_t& i, const char* what) -> const std::string* {
    if (i + 1 >= args.size() || args[i + 1].empty() || args[i + 1].rfind("--", 0) == 0) {
      std::fprintf(stderr, "tensormass bench runtime: %s needs a value\n%s", what, kUsage);
      return nullptr;
    }
    return &args[++i];
  };
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--scaling") {
      options.scaling = true;
    } else if (a == "--quick") {
      options.quick = true;
    } else if (a == "--keep-ccx") {
      options.keep_ccx = true;
    } else if (a == "--json" || a == "--only" || a == "--ccx" || a == "--threads") {
      const std::string* v = value(i, a.c_str());
      if (v == nullptr) {
        exit_code = 2;
        return false;
      }
      if (a == "--json") options.json = *v;
      if (a == "--ccx") options.ccx = *v;
      if (a == "--only") {
        if (*v != "ccx" && *v != "threads" && *v != "implicit" && *v != "quad" && *v != "batch" && *v != "spmv" &&
            *v != "scatter") {
          std::fprintf(stderr,
                       "tensormass bench runtime: --only expects ccx, threads, implicit, quad, batch, spmv or scatter, "
                       "not '%s'\n%s",
                       v->c_str(), kUsage);
          exit_code = 2;
          return false;
        }
        options.only = *v;
      }
      if (a == "--threads") {
        char* stop = nullptr;
        const long n = std::strtol(v->c_str(), &stop, 10);
        if (stop == v->c_str() || *stop != '\0' || n < 1 || n > 1024) {
          std::fprintf(stderr, "tensormass bench runtime: --threads expects a positive integer\n%s", kUsage);
          exit_code = 2;
          return false;
        }
        options.threads = static_cast<int>(n);
      }
    } else if (a == "--help" || a == "-h") {
      std::fputs(kUsage, stdout);
      exit_code = 0;
      return false;
    } else {
      std::fprintf(stderr, "tensormass bench runtime: unknown argument '%s'\n%s", a.c_str(), kUsage);
      exit_code = 2;
      return false;
    }
  }
  return true;
}

}  // namespace

int runtime_command(const std::vector<std::string>& args) {
  Options options;
  int exit_code = 0;
  if (!parse(args, options, exit_code)) return exit_code;
  if (!options.json.empty()) {  // fail now rather than after the run
    const std::string temporary = options.json + ".tmp";
    std::FILE* probe = std::fopen(temporary.c_str(), "w");
    if (probe == nullptr) {
      std::fprintf(stderr, "tensormass bench runtime: cannot write '%s'\n", temporary.c_str());
      return 2;
    }
    std::fclose(probe);
    std::remove(temporary.c_str());
  }
  const auto started = Clock::now();
  std::printf("tensormass bench runtime%s: wall-clock medians over repetitions in this process\n",
              options.quick ? " (quick)" : "");
  std::printf("cpu: %s, %d OpenMP threads available; build: %s\n", cpu_model().c_str(), omp_get_num_procs(),
              TENSORMASS_BENCH_BUILD_INFO);
  const std::string blas = loaded_blas();
  std::printf("BLAS (CHOLMOD's supernodal kernels): %s\n", blas.c_str());
  const std::string load_start = load_average();
  std::printf("load average at start: %s (other processes share these cores: timings are noisy)\n", load_start.c_str());

  std::vector<Target> targets;
  Json report = {{"benchmark", "runtime"},
                 {"quick", options.quick},
                 {"cpu", cpu_model()},
                 {"build", TENSORMASS_BENCH_BUILD_INFO},
                 {"processors", omp_get_num_procs()},
                 {"blas", blas}};
  bool ok = true;
  auto guarded = [&](const char* name, const std::function<bool()>& part) {
    if (!options.only.empty() && options.only != name) return;
    try {
      ok = part() && ok;
    } catch (const std::exception& error) {
      std::fprintf(stderr, "tensormass bench runtime: %s failed: %s\n", name, error.what());
      std::printf("%s: FAILED (%s)\n", name, error.what());
      ok = false;
    }
    std::fflush(stdout);
  };
  Json ccx_json = Json::object(), threads_json = Json::object(), quad_json = Json::object();
  Json implicit_json = Json::array(), batch_json = Json::array(), spmv_json = Json::array(),
       folded_json = Json::array(), scatter_json = Json::array();
  guarded("ccx", [&] { return run_ccx_comparison(options, ccx_json, targets); });
  guarded("threads", [&] { return run_thread_defaults(options, threads_json, targets); });
  guarded("implicit", [&] { return run_implicit_steps(options, implicit_json, targets); });
  guarded("quad", [&] { return run_quad_beam(options, quad_json, targets); });
  guarded("batch", [&] { return run_batched_assembly(options, batch_json, targets); });
  guarded("spmv", [&] {
    return run_block_products(options, spmv_json, targets) && run_folded_products(options, folded_json, targets);
  });
  guarded("scatter", [&] { return run_scatter(options, scatter_json, targets); });
  if (options.only.empty() || options.only == "ccx") report["ccx"] = ccx_json;
  if (options.only.empty() || options.only == "threads") report["threads"] = threads_json;
  if (options.only.empty() || options.only == "implicit") report["implicit"] = implicit_json;
  if (options.only.empty() || options.only == "quad") report["quad_beam"] = quad_json;
  if (options.only.empty() || options.only == "batch") report["batched_assembly"] = batch_json;
  if (options.only.empty() || options.only == "spmv") report["block_products"] = spmv_json;
  if (options.only.empty() || options.only == "spmv") report["folded_products"] = folded_json;
  if (options.only.empty() || options.only == "scatter") report["scatter"] = scatter_json;

  std::printf("\ntargets\n");
  int pass = 0, miss = 0;
  Json target_json = Json::array();
  for (const Target& t : targets) {
    std::printf("  %-58s %10.3g  (target %s %g)  %s\n", t.name.c_str(), t.value, t.relation.c_str(), t.goal,
                t.pass() ? "PASS" : "MISS");
    ++(t.pass() ? pass : miss);
    target_json.push_back({{"name", t.name},
                           {"value", figure(t.value)},
                           {"relation", t.relation},
                           {"goal", figure(t.goal)},
                           {"pass", t.pass()}});
  }
  std::printf("targets: %d PASS, %d MISS\n", pass, miss);
  const double seconds = since(started);
  const std::string load_end = load_average();
  std::printf("done in %.1f s%s; load average at the end: %s\n", seconds, ok ? "" : " (with FAILURES)",
              load_end.c_str());
  report["targets"] = target_json;
  report["seconds"] = figure(seconds);
  report["ok"] = ok;
  report["load_average_start"] = load_start;
  report["load_average_end"] = load_end;
  report["metadata"] = metadata();
  if (!options.json.empty()) {
    if (!write_file_atomically(options.json, json_text(report))) {
      std::fprintf(stderr, "tensormass bench runtime: cannot write '%s'\n", options.json.c_str());
      return 1;
    }
    std::printf("wrote %s\n", options.json.c_str());
  }
  return ok ? 0 : 1;
}

}  // namespace tensormass::bench
