#include "progress_reporter.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace cambio::app {

ProgressReporter::ProgressReporter(std::string label, double total_s)
    : label_(std::move(label)), total_s_(total_s), terminal_(isatty(STDERR_FILENO) == 1) {}

void ProgressReporter::update(double done_s, double wall_elapsed_s) {
  const double fraction = total_s_ > 0 ? std::clamp(done_s / total_s_, 0.0, 1.0) : 1.0;
  const double speed = wall_elapsed_s > 0 ? done_s / wall_elapsed_s : 0.0;
  if (terminal_) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::string bar(static_cast<std::size_t>(filled), '=');
    if (filled < kWidth) bar += '>';
    bar.resize(kWidth, ' ');
    std::fprintf(stderr, "\r%s [%s] %3.0f%%  %.1f/%.1f s  %.2fx real time ", label_.c_str(),
                 bar.c_str(), fraction * 100.0, done_s, total_s_, speed);
    std::fflush(stderr);
    return;
  }
  const int decile = static_cast<int>(fraction * 10.0);
  if (decile > last_decile_) {
    last_decile_ = decile;
    std::fprintf(stderr, "%s: %3d%%  %.1f/%.1f s  %.2fx real time\n", label_.c_str(), decile * 10,
                 done_s, total_s_, speed);
  }
}

void ProgressReporter::finish(double done_s, double wall_elapsed_s) {
  // The last line shows where the run really ended: an interrupted run never claims 100%.
  last_decile_ = -1;
  if (!terminal_ && done_s < total_s_) {
    const double fraction = total_s_ > 0 ? std::clamp(done_s / total_s_, 0.0, 1.0) : 1.0;
    std::fprintf(stderr, "%s: stopped at %.0f%%  %.1f/%.1f s\n", label_.c_str(), fraction * 100.0,
                 done_s, total_s_);
    return;
  }
  update(done_s, wall_elapsed_s);
  if (terminal_) std::fputc('\n', stderr);
}

}  // namespace cambio::app
