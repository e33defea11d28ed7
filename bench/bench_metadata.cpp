#include "bench_metadata.hpp"

#include <omp.h>

#include <ctime>
#include <string>

#include "machine_info.hpp"
#include "tensormass/common/version.hpp"

#ifndef TENSORMASS_BENCH_COMMIT
#define TENSORMASS_BENCH_COMMIT "unknown"
#endif

namespace tensormass::bench {

namespace {

/// Now, UTC, ISO 8601 to the second.
std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

}  // namespace

Json metadata() {
  return {{"tensormass_version", kVersion},
          {"date", utc_now()},
          {"commit", TENSORMASS_BENCH_COMMIT},
          {"machine", cpu_model()},
          {"threads", omp_get_max_threads()}};
}

}  // namespace tensormass::bench
