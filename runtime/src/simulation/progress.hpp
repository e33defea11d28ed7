// Progress of a run on stderr: a redrawn bar on a terminal, plain lines
// (every 10 %) otherwise. Internal header.
#ifndef TENSORMASS_SIMULATION_PROGRESS_HPP
#define TENSORMASS_SIMULATION_PROGRESS_HPP

#include <chrono>
#include <string>

namespace tensormass::detail {

class Progress {
 public:
  Progress(int total, std::string label, bool enabled);
  void update(int done, double mean_step_ms);
  void finish();

 private:
  int total_;
  std::string label_;
  bool enabled_, terminal_;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool drawn_ = false;
};

}  // namespace tensormass::detail

#endif
