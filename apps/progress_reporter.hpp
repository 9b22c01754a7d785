#pragma once

#include <cstdint>
#include <string>

namespace cambio::app {

/// Progress of a long run: a redrawn bar on a terminal, a plain line every 10% otherwise (logs
/// and CI stay readable).
class ProgressReporter {
 public:
  ProgressReporter(std::string label, double total_s);
  void update(double done_s, double wall_elapsed_s);
  /// The final line, at the run time actually done (`done_s` < total when interrupted).
  void finish(double done_s, double wall_elapsed_s);

 private:
  std::string label_;
  double total_s_;
  bool terminal_;
  int last_decile_ = -1;
};

}  // namespace cambio::app
