// The newest accepted reach: the stereo estimate it took and the touch (metric_families.hpp).

#include <cmath>
#include <string>

#include "metric_families.hpp"

namespace cambio::app::detail {

namespace {

constexpr const char* kReachMetrics[] = {"time_to_touch_s", "touch_position_error_m",
                                         "estimated_target_error_m"};

/// time_to_touch_s, touch_position_error_m of an accepted reach.
void touch_metrics(const ReachRecord& reach, MetricsBuilder& out) {
  if (std::isfinite(reach.touch_s)) {
    out.set("time_to_touch_s", reach.touch_s - reach.command_s);
    if (std::isfinite(reach.touch_position_error_m)) {
      out.set("touch_position_error_m", reach.touch_position_error_m);
    } else {
      out.absent("touch_position_error_m",
                 "no target object (evaluation.target_object) to measure the touch against");
    }
  } else {
    const std::string why = std::string("the gripper never touched (the reach ended ") +
                            reach_phase_name(reach.final_phase) + ")";
    out.absent("time_to_touch_s", why);
    out.absent("touch_position_error_m", why);
  }
}

}  // namespace

void reach_metrics(const ScoredTrace& scored, MetricsBuilder& out) {
  const ReachRecord& reach = scored.trace.reach;
  if (!reach.accepted) {
    const std::string why = reach.refused ? "the reach was refused: " + reach.refusal
                                          : std::string("the run made no reach");
    for (const char* name : kReachMetrics) out.absent(name, why);
    return;
  }
  if (std::isfinite(reach.estimated_target_error_m)) {
    out.set("estimated_target_error_m", reach.estimated_target_error_m);
  } else {
    out.absent("estimated_target_error_m",
               "the dominant eye's true axis did not meet the target object at the reach");
  }
  touch_metrics(reach, out);
}

}  // namespace cambio::app::detail
