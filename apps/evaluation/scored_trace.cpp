#include "scored_trace.hpp"

#include <algorithm>
#include <cmath>

namespace cambio::app::detail {

bool ScoredTrace::disparity_within(std::size_t k, double limit) const {
  const TraceRow& row = trace.rows[k];
  return row.disparity_valid && std::abs(row.disparity_px) <= limit;
}

bool ScoredTrace::settled(std::size_t k) const {
  return trace.rows[k].true_gaze_error_deg <= inputs.settle_gaze_error_deg &&
         (!any_disparity || disparity_within(k, inputs.settle_disparity_px));
}

ScoredTrace score_trace(const Trace& trace, const MetricInputs& inputs) {
  ScoredTrace scored{trace, inputs};
  for (const TraceRow& row : trace.rows) {
    scored.any_disparity |= row.disparity_valid;
    scored.any_gaze_error |= std::isfinite(row.true_gaze_error_deg);
  }
  return scored;
}

const CommandTime* last_command(const MetricInputs& inputs,
                                std::initializer_list<control::GazeAction> actions) {
  const CommandTime* found = nullptr;
  for (const CommandTime& command : inputs.commands) {
    if (std::find(actions.begin(), actions.end(), command.action) != actions.end()) {
      found = &command;
    }
  }
  return found;
}

double next_command_s(const MetricInputs& inputs, double time_s) {
  for (const CommandTime& command : inputs.commands) {
    if (command.time_s > time_s) return command.time_s;
  }
  return kInfinity;
}

std::size_t first_row_from(const Trace& trace, double time_s) {
  const auto it = std::lower_bound(trace.rows.begin(), trace.rows.end(), time_s,
                                   [](const TraceRow& row, double t) { return row.time_s < t; });
  return static_cast<std::size_t>(it - trace.rows.begin());
}

double true_pan_rad(const Trace& trace, std::size_t row, int joint) {
  return trace.joints_at(row)[static_cast<std::size_t>(joint)].true_rad;
}

}  // namespace cambio::app::detail
