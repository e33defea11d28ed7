/// \file phase_timer.hpp
/// Internal (not installed): wall-clock timing of the phases a run reports
/// (assembly, solve, criteria, output).
#ifndef TENSORMASS_COMMON_PHASE_TIMER_HPP
#define TENSORMASS_COMMON_PHASE_TIMER_HPP

#include <chrono>

namespace tensormass::detail {

/// Adds the wall time of its lifetime to `seconds`.
class PhaseTimer {
 public:
  explicit PhaseTimer(double& seconds) : seconds_(seconds), start_(std::chrono::steady_clock::now()) {}
  ~PhaseTimer() { seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

 private:
  double& seconds_;
  std::chrono::steady_clock::time_point start_;
};

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace tensormass::detail

#endif
