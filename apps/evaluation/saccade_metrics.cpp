// The last saccade: its duration, the vergence lost on the way, the re-vergence after it
// (metric_families.hpp).

#include <algorithm>
#include <cmath>
#include <string>

#include "metric_families.hpp"

namespace cambio::app::detail {

namespace {

constexpr const char* kSaccadeMetrics[] = {
    "saccade_duration_s", "max_vergence_error_during_saccade_deg", "reverge_time_s"};

void saccade_absent(MetricsBuilder& out, const std::string& why) {
  for (const char* name : kSaccadeMetrics) out.absent(name, why);
}

/// The dominant eye's true pan speed at row k: the backward difference from the row before (0 for
/// the first row and for rows no later than it).
double pan_speed_rad_s(const Trace& trace, int pan, std::size_t k) {
  if (k == 0) return 0.0;
  const double dt = trace.rows[k].time_s - trace.rows[k - 1].time_s;
  if (!(dt > 0.0)) return 0.0;
  return std::abs(true_pan_rad(trace, k, pan) - true_pan_rad(trace, k - 1, pan)) / dt;
}

/// The rows of a saccade commanded at command_s: the first at or after the command, the first
/// where the dominant eye moves, the first after that where it has stopped (rows.size() or past
/// it: never).
struct SaccadeRows {
  std::size_t begin = 0;
  std::size_t moving = 0;
  std::size_t stop = 0;
};

SaccadeRows find_saccade_rows(const ScoredTrace& scored, double command_s) {
  const Trace& trace = scored.trace;
  const auto& rows = trace.rows;
  const std::size_t n = rows.size();
  const int pan = trace.dominant_pan_joint;
  const double stop_speed_rad_s = scored.inputs.stop_speed_rad_s;
  SaccadeRows found;
  found.begin = first_row_from(trace, command_s);
  found.moving = found.begin;
  while (found.moving < n && !rows[found.moving].saccade_active &&
         !(pan_speed_rad_s(trace, pan, found.moving) > stop_speed_rad_s)) {
    ++found.moving;
  }
  found.stop = found.moving + 1;
  while (found.stop < n && (rows[found.stop].saccade_active ||
                            !(pan_speed_rad_s(trace, pan, found.stop) <= stop_speed_rad_s))) {
    ++found.stop;
  }
  return found;
}

/// max_vergence_error_during_saccade_deg over [begin, stop].
void vergence_during_saccade_metrics(const ScoredTrace& scored, const SaccadeRows& saccade,
                                     MetricsBuilder& out) {
  const auto& rows = scored.trace.rows;
  double worst = -kInfinity;
  for (std::size_t k = saccade.begin; k <= saccade.stop; ++k) {
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
}

/// reverge_time_s: from the stop until the disparity holds to the next command (or the end).
void reverge_metrics(const ScoredTrace& scored, const SaccadeRows& saccade, double command_s,
                     MetricsBuilder& out) {
  const auto& rows = scored.trace.rows;
  const std::size_t window_end =
      first_row_from(scored.trace, next_command_s(scored.inputs, command_s));
  const std::size_t reverged = held_from(saccade.stop, window_end, [&](std::size_t k) {
    return scored.disparity_within(k, scored.inputs.reverge_disparity_px);
  });
  if (reverged < window_end) {
    out.set("reverge_time_s", rows[reverged].time_s - rows[saccade.stop].time_s);
  } else {
    out.absent("reverge_time_s", "the eyes never re-verged after the saccade");
  }
}

}  // namespace

void saccade_metrics(const ScoredTrace& scored, MetricsBuilder& out) {
  const CommandTime* command = last_command(scored.inputs, {control::GazeAction::kSaccade});
  if (command == nullptr) {
    saccade_absent(out, "the run sent no saccade command");
    return;
  }
  if (scored.trace.dominant_pan_joint < 0) {
    saccade_absent(out, "the trace does not name the dominant eye's pan joint");
    return;
  }
  const std::size_t n = scored.trace.rows.size();
  const SaccadeRows saccade = find_saccade_rows(scored, command->time_s);
  if (saccade.moving >= n) {
    saccade_absent(out, "the dominant eye never moved after the saccade command");
  } else if (saccade.stop >= n) {
    saccade_absent(out, "the dominant eye never stopped after the saccade command");
  } else {
    out.set("saccade_duration_s", scored.trace.rows[saccade.stop].time_s - command->time_s);
    vergence_during_saccade_metrics(scored, saccade, out);
    reverge_metrics(scored, saccade, command->time_s, out);
  }
}

}  // namespace cambio::app::detail
