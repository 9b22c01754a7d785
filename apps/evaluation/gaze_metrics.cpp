// The metric families of where the eyes look: at the end, while settling and pursuing, and
// whether the target was in view (metric_families.hpp).

#include <algorithm>
#include <cmath>
#include <numbers>

#include "metric_families.hpp"

namespace cambio::app::detail {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

/// max_verging_gaze_error_visible_deg over the rows from `reached`, the first that met the settle
/// thresholds.
void visible_verging_error_metrics(const ScoredTrace& scored, std::size_t reached,
                                   MetricsBuilder& out) {
  const auto& rows = scored.trace.rows;
  const std::size_t n = rows.size();
  if (reached >= n) {
    out.absent("max_verging_gaze_error_visible_deg", "the gaze never met the settle thresholds");
    return;
  }
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
}

}  // namespace

void final_gaze_metrics(const ScoredTrace& scored, MetricsBuilder& out) {
  const auto& rows = scored.trace.rows;
  const std::size_t n = rows.size();
  if (scored.any_disparity) {
    for (std::size_t k = n; k > 0; --k) {
      if (rows[k - 1].disparity_valid) {
        out.set("final_disparity_px", std::abs(rows[k - 1].disparity_px));
        break;
      }
    }
  } else {
    out.absent("final_disparity_px", "no valid disparity was measured");
  }
  if (scored.any_gaze_error) {
    for (std::size_t k = n; k > 0; --k) {
      if (std::isfinite(rows[k - 1].true_gaze_error_deg)) {
        out.set("true_gaze_error_deg", rows[k - 1].true_gaze_error_deg);
        break;
      }
    }
  } else {
    out.absent("true_gaze_error_deg", "the run has no target to score the gaze against");
  }
}

std::size_t settle_metrics(const ScoredTrace& scored, MetricsBuilder& out) {
  // Settling after the last fixate or saccade command.
  const auto& rows = scored.trace.rows;
  const std::size_t n = rows.size();
  const CommandTime* aim =
      last_command(scored.inputs, {control::GazeAction::kFixate, control::GazeAction::kSaccade});
  const double settle_start_s = aim != nullptr ? aim->time_s : rows.front().time_s;
  const std::size_t settle_begin = first_row_from(scored.trace, settle_start_s);
  if (!scored.any_gaze_error) {
    out.absent("settle_time_s", "the run has no target to score the gaze against");
    out.absent("max_verging_gaze_error_visible_deg",
               "the run has no target to score the gaze against");
    return n;
  }
  const auto settled = [&](std::size_t k) { return scored.settled(k); };
  const std::size_t held = held_from(settle_begin, n, settled);
  if (held < n) {
    out.set("settle_time_s", rows[held].time_s - settle_start_s);
  } else {
    out.absent("settle_time_s", "the gaze never settled within the thresholds to the end");
  }
  // First reached, not held: a distractor crossing later must not move the start.
  std::size_t reached = settle_begin;
  while (reached < n && !settled(reached)) ++reached;
  visible_verging_error_metrics(scored, reached, out);
  return reached;
}

void pursuit_metrics(const ScoredTrace& scored, MetricsBuilder& out) {
  const MetricInputs& inputs = scored.inputs;
  const auto& rows = scored.trace.rows;
  const CommandTime* pursue = last_command(inputs, {control::GazeAction::kPursue});
  if (pursue == nullptr) {
    out.absent("pursuit_rms_error_deg", "the run sent no pursue command");
    return;
  }
  const std::size_t begin =
      first_row_from(scored.trace, pursue->time_s + inputs.pursuit_catch_up_s);
  const std::size_t end = first_row_from(scored.trace, next_command_s(inputs, pursue->time_s));
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

void eye_pan_metrics(const ScoredTrace& scored, MetricsBuilder& out) {
  // The neck rule's end state.
  const Trace& trace = scored.trace;
  const std::size_t n = trace.rows.size();
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
}

void occlusion_metrics(const ScoredTrace& scored, MetricsBuilder& out) {
  const auto& rows = scored.trace.rows;
  const std::size_t n = rows.size();
  bool any_target = false;
  double occluded_s = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    any_target |= std::isfinite(rows[k].dominant_gaze_error_deg) ||
                  std::isfinite(rows[k].verging_gaze_error_deg);
    if (!rows[k].target_occluded) continue;
    // Each row lasts until the next; the last as long as the one before.
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
}

}  // namespace cambio::app::detail
