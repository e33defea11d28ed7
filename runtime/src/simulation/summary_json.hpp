// summary.json of a run (internal header).
#ifndef TENSORMASS_SIMULATION_SUMMARY_JSON_HPP
#define TENSORMASS_SIMULATION_SUMMARY_JSON_HPP

#include <string>

#include "tensormass/model/model.hpp"
#include "tensormass/simulation/simulation.hpp"

namespace tensormass::detail {

/// Writes summary.json atomically; `failure` is empty for a successful run.
void write_summary(const std::string& path, const Scene& scene, const Model& model, const RunReport& report,
                   const std::string& failure);

/// The file every evaluation of the adaptive model is streamed to, one JSON
/// object per line (as summary.json's adaptivity.per_step entries).
inline constexpr const char* kAdaptivityRecordsFile = "adaptivity.jsonl";

/// One evaluation's line of kAdaptivityRecordsFile, with its line end.
std::string adaptivity_record_line(const AdaptivityRecord& record);

/// Mean and median of the step times (0 when there are none).
std::pair<double, double> mean_and_median(std::vector<double> values);

}  // namespace tensormass::detail

#endif
