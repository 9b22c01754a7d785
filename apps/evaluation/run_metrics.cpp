#include "run_metrics.hpp"

#include <cmath>
#include <stdexcept>

#include "metric_families.hpp"

namespace cambio::app {

namespace {

void check_inputs(const MetricInputs& inputs) {
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
  check_inputs(inputs);
  detail::MetricsBuilder out;
  if (trace.rows.empty()) {
    for (const std::string_view name : kMetricNames) out.absent(name, "the trace is empty");
    return out.build();
  }
  const detail::ScoredTrace scored = detail::score_trace(trace, inputs);
  detail::final_gaze_metrics(scored, out);
  // The fixation is scored from the first settled row on (metric_families.hpp).
  const std::size_t first_settled = detail::settle_metrics(scored, out);
  detail::saccade_metrics(scored, out);
  detail::pursuit_metrics(scored, out);
  detail::joint_belief_metrics(scored, out);
  detail::fixation_belief_metrics(scored, first_settled, out);
  detail::eye_pan_metrics(scored, out);
  detail::occlusion_metrics(scored, out);
  detail::visit_metrics(scored, out);
  detail::reach_metrics(scored, out);
  return out.build();
}

Json metrics_json(const RunMetrics& metrics) {
  Json json = Json::object();
  for (const auto& [name, value] : metrics.values) json[name] = value;
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
