/// \file paper_report.hpp
/// The pure (untimed) logic of `tensormass bench paper`: the error metric of
/// the origin report's Figure 12, the result rows, and the writers of the
/// JSON file and of the markdown table in the origin's Table 1 layout. Kept
/// apart from the runs so that unit tests can check it on hand-made data.
#ifndef TENSORMASS_BENCH_PAPER_REPORT_HPP
#define TENSORMASS_BENCH_PAPER_REPORT_HPP

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bench_json.hpp"

namespace tensormass::bench {

/// Largest distance between the same node in two displacement fields
/// (node-major, `dim` components per node, equal sizes). Throws
/// std::invalid_argument on a size mismatch or a size not a multiple of dim.
double max_nodal_distance(std::span<const double> a, std::span<const double> b, int dim);

/// The displacements of one run after each step (step 1 first).
using Trajectory = std::vector<std::vector<double>>;

/// The origin's error of a run against the reference (pure StVK) run: the
/// largest nodal distance over all steps, divided by `length` (the beam's
/// length). Both runs must have the same number of steps (else
/// std::invalid_argument): a run that diverged is not comparable.
double trajectory_error(const Trajectory& run, const Trajectory& reference, int dim, double length);

/// The value below which a share `1 - fraction` of `values` lies: the
/// threshold that leaves about `fraction` of the values strictly above it
/// (the elements a criterion would upgrade). fraction in (0, 1).
double upgrade_threshold(std::vector<double> values, double fraction);

double median(std::vector<double> values);
double mean(const std::vector<double>& values);

/// One run of the experiment (one JSON row).
struct PaperRow {
  std::string beam;  ///< "quad 60x10", "hex 30x6x6", ...
  int elements = 0;
  std::string mode;                 ///< hooke, stvk, R_EL, R_V, R_S, R_NL
  std::optional<double> threshold;  ///< none for the pure runs
  double ms_per_step = 0;           ///< median over repetitions of the run's mean ms per step
  double ms_per_step_median = 0;    ///< median over repetitions of the run's median ms per step
  double error = 0;                 ///< trajectory_error against the pure StVK run
  int upgraded = 0;                 ///< elements under StVK at the end (pure stvk: all; hooke: 0)
  double criteria_ms = 0;           ///< criteria time per step (median over repetitions)
  double assembly_ms = 0;           ///< assembly time per step (median over repetitions)
  double solve_ms = 0;              ///< factorisation + solve time per step (median over repetitions)
  std::vector<double> samples;      ///< mean ms per step of each repetition
};

/// The rows as a JSON array, one object per row with the keys beam,
/// elements, mode, threshold (null for pure runs), ms_per_step,
/// ms_per_step_median, error, upgraded, criteria_ms, assembly_ms, solve_ms,
/// samples (numbers in full, null where not finite).
Json rows_json(const std::vector<PaperRow>& rows);

/// The row of `beam` and `mode` (and threshold), or nullptr.
const PaperRow* find_row(const std::vector<PaperRow>& rows, const std::string& beam, const std::string& mode,
                         std::optional<double> threshold = std::nullopt);

}  // namespace tensormass::bench

#endif
