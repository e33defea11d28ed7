#include "simulation/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace tensormass::detail {

Progress::Progress(int total, std::string label, bool enabled)
    : total_(total > 0 ? total : 1),
      label_(std::move(label)),
      enabled_(enabled),
      terminal_(isatty(fileno(stderr)) != 0),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

void Progress::update(int done, double mean_step_ms) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double fraction = static_cast<double>(done) / total_;
  const double eta = done > 0 ? elapsed * (total_ - done) / done : 0.0;
  if (terminal_) {
    if (done < total_ && std::chrono::duration<double>(now - last_draw_).count() < 0.1 && drawn_) return;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::string bar(filled, '#');
    bar.resize(kWidth, '-');
    std::fprintf(stderr, "\r%s %d/%d [%s] %3.0f%%  %.3g ms/step  eta %.1f s ", label_.c_str(), done, total_,
                 bar.c_str(), 100 * fraction, mean_step_ms, eta);
    std::fflush(stderr);
    last_draw_ = now;
    drawn_ = true;
    return;
  }
  const int decile = static_cast<int>(fraction * 10);
  if (decile == last_decile_) return;
  last_decile_ = decile;
  std::fprintf(stderr, "%s %d/%d (%.0f%%), %.3g ms/step, %.1f s elapsed\n", label_.c_str(), done, total_,
               100 * fraction, mean_step_ms, elapsed);
}

void Progress::finish() {
  if (enabled_ && terminal_ && drawn_) std::fputc('\n', stderr);
}

}  // namespace tensormass::detail
