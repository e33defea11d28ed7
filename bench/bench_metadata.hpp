/// \file bench_metadata.hpp
/// The "metadata" member of a benchmark's JSON object: which code ran, when
/// and where.
#ifndef TENSORMASS_BENCH_BENCH_METADATA_HPP
#define TENSORMASS_BENCH_BENCH_METADATA_HPP

#include "bench_json.hpp"

namespace tensormass::bench {

/// {"tensormass_version": kVersion, "date": now, UTC, ISO 8601
/// ("2026-12-02T07:56:00Z"), "commit": the git commit the benchmarks were
/// configured from (bench/CMakeLists.txt; "unknown" without git), "machine":
/// cpu_model(), "threads": omp_get_max_threads()}.
Json metadata();

}  // namespace tensormass::bench

#endif
