#include "run_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>

namespace cambio::app {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

using control::GazeAction;

/// The last command of one of `actions`, or nullptr.
const CommandTime* last_command(const MetricInputs& inputs,
                                std::initializer_list<GazeAction> actions) {
  const CommandTime* found = nullptr;
  for (const CommandTime& command : inputs.commands) {
    if (std::find(actions.begin(), actions.end(), command.action) != actions.end()) {
      found = &command;
    }
  }
  return found;
}

/// The time of the first command after `time_s`, or infinity.
double next_command_s(const MetricInputs& inputs, double time_s) {
  for (const CommandTime& command : inputs.commands) {
    if (command.time_s > time_s) return command.time_s;
  }
  return kInfinity;
}

/// The first row at or after `time_s` (rows.size() if none).
std::size_t first_row_from(const Trace& trace, double time_s) {
  const auto it = std::lower_bound(trace.rows.begin(), trace.rows.end(), time_s,
                                   [](const TraceRow& row, double t) { return row.time_s < t; });
  return static_cast<std::size_t>(it - trace.rows.begin());
}

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

class MetricsBuilder {
 public:
  void set(std::string_view name, double value) { values_[std::string(name)] = value; }
  void absent(std::string_view name, std::string reason) {
    absent_[std::string(name)] = std::move(reason);
  }

  RunMetrics build() const {
    RunMetrics metrics;
    for (const std::string_view name : kMetricNames) {
      const std::string key(name);
      if (const auto it = values_.find(key); it != values_.end()) {
        metrics.values.emplace_back(key, it->second);
      } else if (const auto why = absent_.find(key); why != absent_.end()) {
        metrics.absent.emplace_back(key, why->second);
      } else {
        metrics.absent.emplace_back(key, "not measured in this run");
      }
    }
    return metrics;
  }

 private:
  std::map<std::string, double> values_;
  std::map<std::string, std::string> absent_;
};

double true_pan_rad(const Trace& trace, std::size_t row, int joint) {
  return trace.joints_at(row)[static_cast<std::size_t>(joint)].true_rad;
}

}  // namespace

std::optional<double> RunMetrics::find(std::string_view name) const {
  for (const auto& [key, value] : values) {
    if (key == name) return value;
  }
  return std::nullopt;
}

std::string RunMetrics::absent_reason(std::string_view name) const {
  for (const auto& [key, reason] : absent) {
    if (key == name) return reason;
  }
  return {};
}

RunMetrics compute_metrics(const Trace& trace, const MetricInputs& inputs) {
  for (std::size_t i = 1; i < inputs.commands.size(); ++i) {
    if (inputs.commands[i].time_s < inputs.commands[i - 1].time_s) {
      throw std::invalid_argument("metrics: commands must be in time order");
    }
  }
  if (!(inputs.settle_disparity_px > 0.0) || !(inputs.settle_gaze_error_deg > 0.0) ||
      !(inputs.reverge_disparity_px > 0.0) || !(inputs.pursuit_catch_up_s >= 0.0) ||
      !(inputs.stop_speed_rad_s > 0.0) || !(inputs.visit_dwell_s > 0.0)) {
    throw std::invalid_argument("metrics: thresholds must be positive");
  }
  MetricsBuilder out;
  const auto& rows = trace.rows;
  const std::size_t n = rows.size();
  if (n == 0) {
    for (const std::string_view name : kMetricNames) out.absent(name, "the trace is empty");
    return out.build();
  }

  bool any_disparity = false;
  bool any_gaze_error = false;
  for (const TraceRow& row : rows) {
    any_disparity |= row.disparity_valid;
    any_gaze_error |= std::isfinite(row.true_gaze_error_deg);
  }
  const auto disparity_within = [&](std::size_t k, double limit) {
    return rows[k].disparity_valid && std::abs(rows[k].disparity_px) <= limit;
  };
  // The settle thresholds; disparity only counts in runs that measure it.
  const auto settled = [&](std::size_t k) {
    return rows[k].true_gaze_error_deg <= inputs.settle_gaze_error_deg &&
           (!any_disparity || disparity_within(k, inputs.settle_disparity_px));
  };

  // End-of-run figures.
  if (any_disparity) {
    for (std::size_t k = n; k > 0; --k) {
      if (rows[k - 1].disparity_valid) {
        out.set("final_disparity_px", std::abs(rows[k - 1].disparity_px));
        break;
      }
    }
  } else {
    out.absent("final_disparity_px", "no valid disparity was measured");
  }
  if (any_gaze_error) {
    for (std::size_t k = n; k > 0; --k) {
      if (std::isfinite(rows[k - 1].true_gaze_error_deg)) {
        out.set("true_gaze_error_deg", rows[k - 1].true_gaze_error_deg);
        break;
      }
    }
  } else {
    out.absent("true_gaze_error_deg", "the run has no target to score the gaze against");
  }

  // Settling after the last fixate or saccade command.
  const CommandTime* aim = last_command(inputs, {GazeAction::kFixate, GazeAction::kSaccade});
  const double settle_start_s = aim != nullptr ? aim->time_s : rows.front().time_s;
  const std::size_t settle_begin = first_row_from(trace, settle_start_s);
  std::size_t first_settled = n;  // The first row meeting the settle thresholds (n: none).
  if (!any_gaze_error) {
    out.absent("settle_time_s", "the run has no target to score the gaze against");
    out.absent("max_verging_gaze_error_visible_deg",
               "the run has no target to score the gaze against");
  } else {
    const std::size_t held = held_from(settle_begin, n, settled);
    if (held < n) {
      out.set("settle_time_s", rows[held].time_s - settle_start_s);
    } else {
      out.absent("settle_time_s", "the gaze never settled within the thresholds to the end");
    }
    std::size_t reached = settle_begin;
    while (reached < n && !settled(reached)) ++reached;
    first_settled = reached;
    if (reached < n) {
      double worst = -kInfinity;
      for (std::size_t k = reached; k < n; ++k) {
        if (!rows[k].target_occluded && std::isfinite(rows[k].verging_gaze_error_deg)) {
          worst = std::max(worst, rows[k].verging_gaze_error_deg);
        }
      }
      if (worst > -kInfinity) {
        out.set("max_verging_gaze_error_visible_deg", worst);
      } else {
        out.absent("max_verging_gaze_error_visible_deg",
                   "the verging eye's target was never visible after settling");
      }
    } else {
      out.absent("max_verging_gaze_error_visible_deg", "the gaze never met the settle thresholds");
    }
  }

  // The last saccade: its duration, the vergence lost on the way, the re-vergence after it.
  const CommandTime* saccade = last_command(inputs, {GazeAction::kSaccade});
  const char* saccade_metrics[] = {"saccade_duration_s", "max_vergence_error_during_saccade_deg",
                                   "reverge_time_s"};
  const auto saccade_absent = [&](const std::string& why) {
    for (const char* name : saccade_metrics) out.absent(name, why);
  };
  if (saccade == nullptr) {
    saccade_absent("the run sent no saccade command");
  } else if (trace.dominant_pan_joint < 0) {
    saccade_absent("the trace does not name the dominant eye's pan joint");
  } else {
    const int pan = trace.dominant_pan_joint;
    const auto speed_rad_s = [&](std::size_t k) {
      if (k == 0) return 0.0;
      const double dt = rows[k].time_s - rows[k - 1].time_s;
      if (!(dt > 0.0)) return 0.0;
      return std::abs(true_pan_rad(trace, k, pan) - true_pan_rad(trace, k - 1, pan)) / dt;
    };
    const std::size_t begin = first_row_from(trace, saccade->time_s);
    std::size_t moving = begin;
    while (moving < n && !rows[moving].saccade_active &&
           !(speed_rad_s(moving) > inputs.stop_speed_rad_s)) {
      ++moving;
    }
    std::size_t stop = moving + 1;
    while (stop < n &&
           (rows[stop].saccade_active || !(speed_rad_s(stop) <= inputs.stop_speed_rad_s))) {
      ++stop;
    }
    if (moving >= n) {
      saccade_absent("the dominant eye never moved after the saccade command");
    } else if (stop >= n) {
      saccade_absent("the dominant eye never stopped after the saccade command");
    } else {
      out.set("saccade_duration_s", rows[stop].time_s - saccade->time_s);
      double worst = -kInfinity;
      for (std::size_t k = begin; k <= stop; ++k) {
        if (std::isfinite(rows[k].verging_gaze_error_deg)) {
          worst = std::max(worst, rows[k].verging_gaze_error_deg);
        }
      }
      if (worst > -kInfinity) {
        out.set("max_vergence_error_during_saccade_deg", worst);
      } else {
        out.absent("max_vergence_error_during_saccade_deg",
                   "the verging eye had no target point during the saccade");
      }
      const std::size_t window_end = first_row_from(trace, next_command_s(inputs, saccade->time_s));
      const std::size_t reverged = held_from(stop, window_end, [&](std::size_t k) {
        return disparity_within(k, inputs.reverge_disparity_px);
      });
      if (reverged < window_end) {
        out.set("reverge_time_s", rows[reverged].time_s - rows[stop].time_s);
      } else {
        out.absent("reverge_time_s", "the eyes never re-verged after the saccade");
      }
    }
  }

  // Pursuit.
  const CommandTime* pursue = last_command(inputs, {GazeAction::kPursue});
  if (pursue == nullptr) {
    out.absent("pursuit_rms_error_deg", "the run sent no pursue command");
  } else {
    const std::size_t begin = first_row_from(trace, pursue->time_s + inputs.pursuit_catch_up_s);
    const std::size_t end = first_row_from(trace, next_command_s(inputs, pursue->time_s));
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t k = begin; k < end; ++k) {
      const double e = rows[k].dominant_gaze_error_deg;
      if (!std::isfinite(e)) continue;
      sum += e * e;
      ++count;
    }
    if (count > 0) {
      out.set("pursuit_rms_error_deg", std::sqrt(sum / static_cast<double>(count)));
    } else {
      out.absent("pursuit_rms_error_deg", "no scored sample after the pursuit's catch-up time");
    }
  }

  // Believed against true.
  double joint_error = -kInfinity;
  for (const TraceJointSample& joint : trace.joints) {
    const double e = std::abs(joint.believed_rad - joint.true_rad);
    if (std::isfinite(e)) joint_error = std::max(joint_error, e);
  }
  if (joint_error > -kInfinity) {
    out.set("max_believed_vs_true_joint_error_rad", joint_error);
  } else {
    out.absent("max_believed_vs_true_joint_error_rad", "no joint had both believed and true");
  }
  // From the first settled row on: with the eyes (nearly) parallel the two axes meet far away or
  // nowhere, and the distance between two such points says nothing about either.
  double fixation_max = -kInfinity, fixation_final = kInfinity;
  for (std::size_t k = first_settled; k < n; ++k) {
    const TraceRow& row = rows[k];
    if (!std::isfinite(row.fixation_error_m)) continue;
    fixation_max = std::max(fixation_max, row.fixation_error_m);
    fixation_final = row.fixation_error_m;
  }
  if (fixation_max > -kInfinity) {
    out.set("final_believed_vs_true_fixation_error_m", fixation_final);
    out.set("max_believed_vs_true_fixation_error_m", fixation_max);
  } else {
    const char* why = "no sample after the gaze settled had both a believed and a true fixation";
    out.absent("final_believed_vs_true_fixation_error_m", why);
    out.absent("max_believed_vs_true_fixation_error_m", why);
  }

  // The neck rule's end state.
  double pan_deg = -kInfinity;
  for (const int joint : {trace.dominant_pan_joint, trace.verging_pan_joint}) {
    if (joint < 0) continue;
    const double value = std::abs(true_pan_rad(trace, n - 1, joint)) * kDegPerRad;
    if (std::isfinite(value)) pan_deg = std::max(pan_deg, value);
  }
  if (pan_deg > -kInfinity) {
    out.set("final_max_abs_eye_pan_deg", pan_deg);
  } else {
    out.absent("final_max_abs_eye_pan_deg", "the trace does not name the eyes' pan joints");
  }

  // Occlusion.
  bool any_target = false;
  double occluded_s = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    any_target |= std::isfinite(rows[k].dominant_gaze_error_deg) ||
                  std::isfinite(rows[k].verging_gaze_error_deg);
    if (!rows[k].target_occluded) continue;
    if (k + 1 < n) {
      occluded_s += rows[k + 1].time_s - rows[k].time_s;
    } else if (k > 0) {
      occluded_s += rows[k].time_s - rows[k - 1].time_s;
    }
  }
  if (any_target) {
    out.set("target_occluded_s", occluded_s);
  } else {
    out.absent("target_occluded_s", "the run has no target point");
  }

  if (trace.visit_objects.empty()) {
    for (const char* name : {"objects_visited", "all_objects_visited_s"}) {
      out.absent(name, "the experiment names no evaluation.visit_objects");
    }
  } else {
    const auto visits = object_visit_times(trace, inputs.visit_dwell_s);
    double visited = 0.0;
    double last_s = 0.0;
    std::string missed;
    for (std::size_t i = 0; i < visits.size(); ++i) {
      if (visits[i]) {
        visited += 1.0;
        last_s = std::max(last_s, *visits[i]);
      } else {
        missed += (missed.empty() ? "" : ", ") + trace.visit_objects[i];
      }
    }
    out.set("objects_visited", visited);
    if (missed.empty()) {
      out.set("all_objects_visited_s", last_s);
    } else {
      out.absent("all_objects_visited_s", "never visited: " + missed);
    }
  }
  // The reach.
  const ReachRecord& reach = trace.reach;
  const char* reach_metrics[] = {"time_to_touch_s", "touch_position_error_m",
                                 "estimated_target_error_m"};
  if (!reach.accepted) {
    const std::string why = reach.refused ? "the reach was refused: " + reach.refusal
                                          : std::string("the run made no reach");
    for (const char* name : reach_metrics) out.absent(name, why);
  } else {
    if (std::isfinite(reach.estimated_target_error_m)) {
      out.set("estimated_target_error_m", reach.estimated_target_error_m);
    } else {
      out.absent("estimated_target_error_m",
                 "the dominant eye's true axis did not meet the target object at the reach");
    }
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
  return out.build();
}

std::vector<std::optional<double>> object_visit_times(const Trace& trace, double dwell_s) {
  std::vector<std::optional<double>> visits(trace.visit_objects.size());
  int resting_on = -1;  // The object of the current run of rows, -1 for none.
  double since_s = 0.0;
  for (const TraceRow& row : trace.rows) {
    const bool still = !(row.gaze_status && row.saccade_active);
    const int object = still ? row.axis_object : -1;
    if (object != resting_on) {
      resting_on = object;
      since_s = row.time_s;
    }
    if (object < 0 || object >= static_cast<int>(visits.size())) continue;
    auto& visit = visits[static_cast<std::size_t>(object)];
    // Row times are sums of periods: a dwell of whole periods may fall short by rounding.
    if (!visit && row.time_s - since_s >= dwell_s - 1e-9) visit = row.time_s;
  }
  return visits;
}

Json visits_json(const Trace& trace, double dwell_s) {
  Json json = Json::object();
  const auto visits = object_visit_times(trace, dwell_s);
  for (std::size_t i = 0; i < visits.size(); ++i) {
    json[trace.visit_objects[i]] = visits[i] ? Json(*visits[i]) : Json(nullptr);
  }
  return json;
}

std::vector<GoalResult> evaluate_goals(const RunMetrics& metrics, std::span<const Goal> goals) {
  std::vector<GoalResult> results;
  for (const Goal& goal : goals) {
    GoalResult result;
    result.goal = goal;
    result.value = metrics.find(goal.metric);
    const bool is_max = goal.bound == GoalBound::kMax;
    if (!result.value) {
      const std::string why = metrics.absent_reason(goal.metric);
      result.reason = "absent: " + (why.empty() ? std::string("no such metric") : why);
    } else if (!std::isfinite(*result.value)) {
      result.reason = "the value is not finite";
    } else if (is_max ? *result.value <= goal.value : *result.value >= goal.value) {
      result.passed = true;
    } else {
      result.reason = is_max ? "above the maximum" : "below the minimum";
    }
    results.push_back(std::move(result));
  }
  return results;
}

bool all_passed(std::span<const GoalResult> results) {
  return std::all_of(results.begin(), results.end(),
                     [](const GoalResult& result) { return result.passed; });
}

Json metrics_json(const RunMetrics& metrics) {
  Json json = Json::object();
  for (const auto& [name, value] : metrics.values) json[name] = value;
  return json;
}

Json goals_json(std::span<const GoalResult> results) {
  Json json = Json::object();
  for (const GoalResult& result : results) {
    Json& entry = json[result.goal.metric];
    const bool first = !entry.contains("passed");
    entry[result.goal.bound == GoalBound::kMax ? "max" : "min"] = result.goal.value;
    entry["value"] = result.value ? Json(*result.value) : Json(nullptr);
    entry["passed"] = (first || entry["passed"].get<bool>()) && result.passed;
    if (!result.reason.empty()) {
      entry["reason"] = entry.contains("reason")
                            ? entry["reason"].get<std::string>() + "; " + result.reason
                            : result.reason;
    }
  }
  return json;
}

Json final_joints_json(const Trace& trace) {
  Json json = Json::object();
  if (trace.rows.empty()) return json;
  const auto last = trace.joints_at(trace.rows.size() - 1);
  const auto number = [](double value) { return std::isfinite(value) ? Json(value) : Json(); };
  for (std::size_t i = 0; i < trace.joint_count(); ++i) {
    json[trace.joint_names[i]] = {{"believed_rad", number(last[i].believed_rad)},
                                  {"true_rad", number(last[i].true_rad)},
                                  {"command_rad", number(last[i].command_rad)}};
  }
  return json;
}

}  // namespace cambio::app
