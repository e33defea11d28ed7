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

}  // namespace tensormass::bench
