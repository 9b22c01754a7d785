#pragma once

// Internal to cambio_evaluation: the questions the metric families (metric_families.hpp) ask of
// a trace and of the commands a run sent.

#include <cstddef>
#include <initializer_list>
#include <limits>

#include "run_metrics.hpp"

namespace cambio::app::detail {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// A non-empty trace with the inputs it is scored against, and what several families need to
/// know of all its rows.
struct ScoredTrace {
  const Trace& trace;
  const MetricInputs& inputs;
  bool any_disparity = false;   ///< Some row has a valid disparity.
  bool any_gaze_error = false;  ///< Some row has a finite true gaze error.

  /// Row k has a valid |disparity| <= limit.
  bool disparity_within(std::size_t k, double limit) const;
  /// Row k meets the settle thresholds; disparity only counts in runs that measure it.
  bool settled(std::size_t k) const;
};

/// Scans the rows once for any_disparity and any_gaze_error.
ScoredTrace score_trace(const Trace& trace, const MetricInputs& inputs);

/// The last command of one of `actions`, or nullptr.
const CommandTime* last_command(const MetricInputs& inputs,
                                std::initializer_list<control::GazeAction> actions);

/// The time of the first command after `time_s`, or infinity.
double next_command_s(const MetricInputs& inputs, double time_s);

/// The first row at or after `time_s` (rows.size() if none).
std::size_t first_row_from(const Trace& trace, double time_s);

/// The first row of [begin, end) from which `holds` is true for every row up to end; `end` if
/// the last row does not hold.
template <class Predicate>
std::size_t held_from(std::size_t begin, std::size_t end, Predicate holds) {
  std::size_t first = end;
  for (std::size_t k = end; k > begin; --k) {
    if (!holds(k - 1)) break;
    first = k - 1;
  }
  return first;
}

double true_pan_rad(const Trace& trace, std::size_t row, int joint);

}  // namespace cambio::app::detail
