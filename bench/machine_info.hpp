// What the benchmarks report about the machine they ran on.
#ifndef TENSORMASS_BENCH_MACHINE_INFO_HPP
#define TENSORMASS_BENCH_MACHINE_INFO_HPP

#include <string>

namespace tensormass::bench {

/// The "model name" of /proc/cpuinfo, or "unknown CPU".
std::string cpu_model();
/// The first three fields of /proc/loadavg (1, 5, 15 minutes): how busy the machine was.
std::string load_average();

}  // namespace tensormass::bench

#endif
