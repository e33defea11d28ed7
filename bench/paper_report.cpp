// The untimed logic of `tensormass bench paper`: see paper_report.hpp.
#include "paper_report.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace tensormass::bench {

double max_nodal_distance(std::span<const double> a, std::span<const double> b, int dim) {
  if (dim < 1 || a.size() != b.size() || a.size() % static_cast<std::size_t>(dim) != 0)
    throw std::invalid_argument("max_nodal_distance: fields of different sizes or not a multiple of dim");
  double worst = 0.0;
  for (std::size_t node = 0; node < a.size(); node += static_cast<std::size_t>(dim)) {
    double d2 = 0.0;
    for (int c = 0; c < dim; ++c) {
      const double d = a[node + c] - b[node + c];
      d2 += d * d;
    }
    // NaN propagates (a diverged run must not look exact).
    if (!(d2 <= worst * worst)) worst = std::sqrt(d2);
  }
  return worst;
}

double trajectory_error(const Trajectory& run, const Trajectory& reference, int dim, double length) {
  if (run.size() != reference.size())
    throw std::invalid_argument("trajectory_error: " + std::to_string(run.size()) + " steps against " +
                                std::to_string(reference.size()) + " in the reference");
  if (!(length > 0)) throw std::invalid_argument("trajectory_error: the length must be positive");
  double worst = 0.0;
  for (std::size_t step = 0; step < run.size(); ++step) {
    const double d = max_nodal_distance(run[step], reference[step], dim);
    if (!(d <= worst)) worst = d;
  }
  return worst / length;
}

double upgrade_threshold(std::vector<double> values, double fraction) {
  if (values.empty() || !(fraction > 0 && fraction < 1))
    throw std::invalid_argument("upgrade_threshold: needs values and a fraction in (0, 1)");
  std::sort(values.begin(), values.end());
  // Leave round(fraction * n) values strictly above: the threshold is the
  // largest value that stays (the one just below the upgraded ones).
  const auto n = values.size();
  if (n == 1) return values[0];
  auto above = static_cast<std::size_t>(std::llround(fraction * static_cast<double>(n)));
  above = std::clamp<std::size_t>(above, 1, n - 1);
  return values[n - 1 - above];
}

double median(std::vector<double> values) {
  if (values.empty()) return NAN;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double mean(const std::vector<double>& values) {
  if (values.empty()) return NAN;
  double sum = 0.0;
  for (const double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

Json rows_json(const std::vector<PaperRow>& rows) {
  Json list = Json::array();
  for (const PaperRow& r : rows)
    list.push_back({{"beam", r.beam},
                    {"elements", r.elements},
                    {"mode", r.mode},
                    {"threshold", r.threshold ? number(*r.threshold) : Json(nullptr)},
                    {"ms_per_step", number(r.ms_per_step)},
                    {"ms_per_step_median", number(r.ms_per_step_median)},
                    {"error", number(r.error)},
                    {"upgraded", r.upgraded},
                    {"criteria_ms", number(r.criteria_ms)},
                    {"assembly_ms", number(r.assembly_ms)},
                    {"solve_ms", number(r.solve_ms)},
                    {"samples", numbers(r.samples)}});
  return list;
}

const PaperRow* find_row(const std::vector<PaperRow>& rows, const std::string& beam, const std::string& mode,
                         std::optional<double> threshold) {
  for (const PaperRow& r : rows)
    if (r.beam == beam && r.mode == mode && (!threshold || (r.threshold && *r.threshold == *threshold))) return &r;
  return nullptr;
}

namespace {

const std::array<const char*, 4> kCriteria{"R_EL", "R_V", "R_S", "R_NL"};

std::string format(const char* pattern, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

/// Three figures, without exponent for the usual ranges.
std::string figure(double value) {
  if (!std::isfinite(value)) return "n/a";
  const double a = std::abs(value);
  if (a != 0 && (a < 1e-3 || a >= 1e5)) return format("%.2e", value);
  if (a >= 100) return format("%.0f", value);
  if (a >= 10) return format("%.1f", value);
  if (a >= 1) return format("%.2f", value);
  return format("%.3g", value);
}

std::vector<const PaperRow*> adaptive_rows(const std::vector<PaperRow>& rows, const std::string& beam,
                                           const std::string& mode) {
  std::vector<const PaperRow*> out;
  for (const PaperRow& r : rows)
    if (r.beam == beam && r.mode == mode && r.threshold) out.push_back(&r);
  std::sort(out.begin(), out.end(), [](const PaperRow* a, const PaperRow* b) { return *a->threshold < *b->threshold; });
  return out;
}

}  // namespace

std::string markdown_table(const std::vector<PaperRow>& rows, const std::string& beam, int origin) {
  // The origin's rows (ms per step, thresholds 1.5 / 3 / 6 % and 15 / 30 / 60).
  struct OriginRow {
    const char* mode;
    std::array<const char*, 3> ms600, ms300;
  };
  static const std::array<OriginRow, 6> kOrigin{{{"hooke", {"0.102", "", ""}, {"0.031", "", ""}},
                                                 {"R_EL", {"2.690", "0.561", "0.125"}, {"1.028", "0.212", "0.048"}},
                                                 {"R_V", {"4.093", "1.396", "0.190"}, {"2.143", "0.753", "0.110"}},
                                                 {"R_S", {"8.668", "8.058", "7.067"}, {"-", "-", "-"}},
                                                 {"R_NL", {"", "", ""}, {"", "", ""}},
                                                 {"stvk", {"16.273", "", ""}, {"9.011", "", ""}}}};
  const bool with_origin = origin == 600 || origin == 300;
  std::string out = "| " + beam + " | ours: ms per step (threshold; error; upgraded) | | |";
  if (with_origin) out += " origin, " + std::to_string(origin) + " el.: ms per step | | |";
  out += "\n|---|---|---|---|";
  if (with_origin) out += "---|---|---|";
  out += "\n";
  for (const OriginRow& o : kOrigin) {
    const std::string mode = o.mode;
    const bool pure = mode == "hooke" || mode == "stvk";
    std::array<std::string, 3> cells;
    if (pure) {
      if (const PaperRow* r = find_row(rows, beam, mode))
        cells[0] =
            "**" + figure(r->ms_per_step) + "** (-; " + figure(r->error) + "; " + std::to_string(r->upgraded) + ")";
    } else {
      const auto adaptive = adaptive_rows(rows, beam, mode);
      for (std::size_t i = 0; i < adaptive.size() && i < 3; ++i)
        cells[i] = "**" + figure(adaptive[i]->ms_per_step) + "** (" + figure(*adaptive[i]->threshold) + "; " +
                   figure(adaptive[i]->error) + "; " + std::to_string(adaptive[i]->upgraded) + ")";
      // A mode without runs keeps its row only for the origin's numbers.
      const auto& origin_ms = origin == 600 ? o.ms600 : o.ms300;
      if (adaptive.empty() && (!with_origin || std::string(origin_ms[0]).empty())) continue;
    }
    const std::string label = mode == "hooke" ? "Hooke" : mode == "stvk" ? "StVK" : mode;
    out += "| " + label + " | " + cells[0] + " | " + cells[1] + " | " + cells[2] + " |";
    if (with_origin) {
      const auto& ms = origin == 600 ? o.ms600 : o.ms300;
      out += std::string(" ") + ms[0] + " | " + ms[1] + " | " + ms[2] + " |";
    }
    out += "\n";
  }
  return out;
}

std::string markdown_ratios(const std::vector<PaperRow>& rows, const std::string& beam) {
  const PaperRow* hooke = find_row(rows, beam, "hooke");
  const PaperRow* stvk = find_row(rows, beam, "stvk");
  if (!hooke || !stvk) return "";
  std::string out =
      "| " + beam + " | threshold | ms per step | / StVK | position (0 = Hooke, 1 = StVK) | error | " +
      "error / Hooke's | upgraded | criteria ms per step | assembly ms per step | factorisation + solve ms per step |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|\n";
  const double span = stvk->ms_per_step - hooke->ms_per_step;
  auto line = [&](const PaperRow& r, const std::string& label) {
    out += "| " + label + " | " + (r.threshold ? figure(*r.threshold) : std::string("-")) + " | " +
           figure(r.ms_per_step) + " | " + format("%.2f", r.ms_per_step / stvk->ms_per_step) + " | " +
           format("%.2f", span != 0 ? (r.ms_per_step - hooke->ms_per_step) / span : NAN) + " | " + figure(r.error) +
           " | " + (hooke->error > 0 ? format("%.2f", r.error / hooke->error) : std::string("-")) + " | " +
           std::to_string(r.upgraded) + " / " + std::to_string(r.elements) + " | " + figure(r.criteria_ms) + " | " +
           figure(r.assembly_ms) + " | " + figure(r.solve_ms) + " |\n";
  };
  line(*hooke, "Hooke");
  for (const char* mode : kCriteria)
    for (const PaperRow* r : adaptive_rows(rows, beam, mode)) line(*r, mode);
  line(*stvk, "StVK");
  out += "\nStVK / Hooke (ms per step): **" + format("%.2f", stvk->ms_per_step / hooke->ms_per_step) +
         "** (origin: " + format("%.0f", OriginTable::stvk_600 / OriginTable::hooke_600) + " on 600 elements, " +
         format("%.0f", OriginTable::stvk_300 / OriginTable::hooke_300) + " on 300).\n";
  return out;
}

}  // namespace tensormass::bench

namespace tensormass::bench {

std::string paper_markdown_header(const std::string& run, const std::string& cpu, const std::string& load,
                                  const std::string& build, int steps, double dt, int repetitions_2d,
                                  int repetitions_3d) {
  std::string out;
  out += "# The origin report's experiment: `tensormass bench paper`\n\n";
  out +=
      "Table 1 and Figure 12 of the origin report (Caillaud, LIRIS; `docs/architecture.md`) on our code: 2D cantilever "
      "beams "
      "of 60 x 10 and 30 x 10 square quads under gravity, pure Hooke, pure StVK, and adaptive runs (every element "
      "starts under Hooke and is upgraded to StVK when its criterion exceeds the threshold), then the same on 3D "
      "tet, hex and mixed beams. Generated by the bench (run: " +
      run + "); do not edit by hand.\n\n";
  out +=
      "## Reproduce\n\n```sh\ncmake -S . -B build -G Ninja && cmake --build build\n"
      "./build/tensormass bench paper            # full run: writes docs/results/paper.{md,json} and the plots\n"
      "./build/tensormass bench paper --quick --out /tmp/paper   # about 2 minutes\n"
      "./build/tensormass bench paper --smoke    # CI smoke test, seconds\n"
      "/usr/bin/python3 bench/plot_paper.py docs/results/paper.json docs/results   # the plots again\n```\n\n";
  out += "## Machine and method\n\n";
  out += "- CPU: `" + cpu + "`, one thread (OpenMP and BLAS); load average at the end of the run: " + load +
         " (the machine is shared: expect a few percent of noise).\n";
  out += "- Build: " + build + ".\n";
  char buffer[512];
  std::snprintf(buffer, sizeof buffer,
                "- Every run: implicit (backward) Euler, dt = %g s, %d steps (%.2g s), one Newton iteration per step "
                "(the linearised step), CHOLMOD; gravity (9.81 m/s^2 along -y) ramped in over the first second, "
                "Rayleigh mass damping 4 /s (the 6 m beam's first mode is critically damped at about 5.6 /s), so "
                "the beam bends down to near its static sag without a violent swing; plane strain in 2D (unit "
                "thickness); nu = 0.3, rho = 1000 kg/m^3; clamped at x = 0 (every node of the clamp face).\n",
                dt, steps, dt * steps);
  out += buffer;
  out +=
      "- Material: the origin gives none. E = 1e7 Pa on the 6 m beams (H = 1 m): the static tip sag is about "
      "1.7 m, 28 % of L; the 3 m x 1 m beam has E = 1.25e6 Pa, so that rho g L^3 / (E H^2), hence the sag over "
      "L, is the same (the thicker short beam then has about twice the strain at the clamp). 3D beams: 6 x 1 x 1 m, "
      "E = 1e7 Pa.\n";
  std::snprintf(buffer, sizeof buffer,
                "- Time per step: the wall time from the end of one step to the end of the next step's adaptivity "
                "update (solve, criteria, switches), the first step (CHOLMOD's symbolic analysis) not counted. Each "
                "run gives its mean (and median) over the steps; the figure quoted is the median over %d repetitions "
                "(2D) or %d (3D); one repetition runs every configuration once, in turn.\n",
                repetitions_2d, repetitions_3d);
  out += buffer;
  out +=
      "- Error (Figure 12): the largest distance between a node in the run and the same node in the pure StVK "
      "run, over all nodes and all steps, divided by the beam's length L.\n";
  out += "- Upgraded: elements under StVK at the end (no downgrade, no blending: the origin switches at once).\n";
  out +=
      "- R_S thresholds: each element's largest R_S over a pure Hooke run (R_S evaluated, nothing switching); "
      "the thresholds leave 1/2, 1/5 and 1/20 of the elements above. In an adaptive run the upgrades change "
      "the forces, so the counts differ somewhat.\n";
  return out;
}

std::string paper_markdown_footer() {
  return "\n## Plots\n\n"
         "Error against threshold per criterion (the origin's Figure 12; thresholds of R_S scaled by the smallest "
         "one so all fit one axis):\n\n![error against threshold](paper_threshold.png)\n\n"
         "Error against time per step for every run (which criterion buys the most accuracy per millisecond):\n\n"
         "![error against time per step](paper_error_time.png)\n\n"
         "## What the criteria see\n\n"
         "- R_EL (edge lengths) and R_V (area or volume) are invariant under rotation: an element that rotates "
         "without stretching passes them. Under Hooke, a rigid rotation is not strain-free (the linear strain of a "
         "rotation by theta is about 1 - cos theta on the diagonal): such elements inflate and stiffen the beam, yet "
         "R_EL and R_V never upgrade them. In large-rotation bending (the tip of a sagging cantilever) this leaves "
         "Hooke elements exactly where the linear law errs most.\n"
         "- R_NL (the quadratic part of the Green-Lagrange strain, 1/2 H^T H) grows with rotation as well as strain, "
         "so it upgrades the rotated elements.\n"
         "- R_S averages the assembled nodal forces over the element: (1/v) integral of sum_j N_j f_j is a force "
         "(N), not a force per volume as criteria.hpp says. Under gravity every interior node carries about the "
         "same weight, so R_S is nearly uniform over the interior and large only at the clamp (the reaction) and "
         "along the boundary: its upgrade count falls off a cliff around the interior value (see the calibrated "
         "thresholds: the bisection cannot always reach 1/5 and 1/20), and it does not see rotation either. "
         "Upgrading an element changes the forces of its neighbours, which can cascade.\n"
         "- R_S also costs one extra assembly of the internal forces per step (Adaptivity::evaluate calls "
         "Assembler::assemble at the new state, which the next implicit step assembles again): this is most of "
         "its overhead in the table above.\n"
         "\n## Why the times look like this\n\n"
         "- Pure Hooke with one Newton iteration per step assembles the same stiffness matrix at every step, and "
         "the CHOLMOD solver keeps its factor when the matrix is unchanged: a Hooke step is an assembly and two "
         "triangular solves. A StVK element changes the matrix at every step, so a StVK step also refactorises. "
         "StVK / Hooke therefore compares a factorisation with none, not the two laws' kernels: compare the "
         "assembly columns for the kernels' cost.\n"
         "- For the same reason, as soon as ONE element is upgraded every later step refactorises: an adaptive "
         "step then costs about a StVK step, whatever the number of upgraded elements. An adaptive run's mean "
         "time sits between Hooke and StVK according to how many steps ran before the first switch (the median "
         "per step tells on which side of the first switch most steps fell). The origin's Table 1, where the "
         "time follows the share of upgraded elements, reflects a solver whose cost is per element.\n"
         "- The criteria run on every element at every step (`every: 1`); their cost (tens of ns per element) "
         "is small against a refactorising step but not against a Hooke step that reuses its factor, hence the "
         "overhead table. Evaluating them every few steps (`adaptivity.every`) divides it accordingly.\n";
}

}  // namespace tensormass::bench
