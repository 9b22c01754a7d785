#include "gaze_bench_score.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cambio::app {

namespace {

bool has(double value) {
  return std::isfinite(value);
}

/// How long row k lasts: until the next row (the last as long as the one before).
double row_duration_s(const std::vector<TraceRow>& rows, std::size_t k) {
  if (rows.size() < 2) return 0.0;
  const std::size_t next = std::min(k + 1, rows.size() - 1);
  const std::size_t from = next == k ? k - 1 : k;
  return rows[next].time_s - rows[from].time_s;
}

std::string describe(const char* format, double value) {
  char text[160];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace

GazeRunScore score_gaze_run(const GeneratedGazeRun& run, const Trace& trace,
                            const GazeScoreSettings& settings) {
  GazeRunScore score;
  const std::vector<TraceRow>& rows = trace.rows;
  if (rows.empty()) {
    score.failure = "the run recorded nothing";
    return score;
  }

  // Where scoring starts: the start, or the dominant eye's stop after a saccade.
  double from_s = rows.front().time_s;
  if (run.task == GazeBenchTask::kSaccadeDepth) {
    bool moving = false;
    for (const TraceRow& row : rows) {
      if (row.time_s < run.saccade_at_s) continue;
      moving = moving || row.saccade_active;
      if (moving && !row.saccade_active) {
        score.saccade_stop_s = row.time_s;
        break;
      }
    }
    if (!score.saccade_stop_s) {
      score.failure = "the saccade never ended";
      return score;
    }
    from_s = *score.saccade_stop_s;
  }

  // Calibration: each new measurement against the truth of its row.
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const TraceRow& row = rows[k];
    if (!row.disparity_valid || !has(row.disparity_px) || !has(row.true_disparity_px)) continue;
    if (k > 0 && rows[k - 1].disparity_px == row.disparity_px &&
        rows[k - 1].disparity_confidence == row.disparity_confidence) {
      continue;
    }
    if (row.saccade_active) continue;  // Frames exposed mid-saccade: no truth at one instant.
    score.calibration.push_back(
        {row.disparity_confidence,
         std::abs(row.disparity_px - row.true_disparity_px) <= settings.calibration_tolerance_px});
  }

  if (run.task == GazeBenchTask::kPursuit) {
    double sum_sq = 0.0;
    int n = 0;
    for (const TraceRow& row : rows) {
      if (row.time_s < run.pursue_at_s + settings.pursuit_catch_up_s) continue;
      if (!has(row.dominant_gaze_error_deg)) continue;
      sum_sq += row.dominant_gaze_error_deg * row.dominant_gaze_error_deg;
      ++n;
    }
    if (n == 0) {
      score.failure = "no row had the dominant eye's gaze error while pursuing";
      return score;
    }
    score.pursuit_rms_deg = std::sqrt(sum_sq / n);
    score.final_error_deg = rows.back().dominant_gaze_error_deg;
    const double bound = run.pursuit_speed_deg_s > settings.pursuit_fast_above_deg_s
                             ? settings.pursuit_rms_fast_deg
                             : settings.pursuit_rms_slow_deg;
    score.success = *score.pursuit_rms_deg <= bound;
    if (!score.success) {
      score.failure = describe("pursuit RMS error %.2f deg", *score.pursuit_rms_deg) +
                      describe(" above %.1f deg", bound);
    }
    return score;
  }

  // The verging eye, from from_s.
  std::optional<double> held_from;
  const TraceRow* last_seen = nullptr;
  double stretch_s = 0.0;  // The current unbroken stretch off the target.
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const TraceRow& row = rows[k];
    if (row.time_s < from_s) continue;
    if (row.target_occluded) {
      score.occluded_s += row_duration_s(rows, k);
      continue;
    }
    if (!has(row.verging_gaze_error_deg)) continue;
    last_seen = &row;
    const bool verged = row.verging_gaze_error_deg <= settings.verged_deg;
    if (verged && !score.first_verged_s) score.first_verged_s = row.time_s - from_s;
    if (verged && !held_from) held_from = row.time_s - from_s;
    if (!verged) held_from.reset();
    if (score.first_verged_s) {
      score.worst_error_deg =
          std::max(score.worst_error_deg.value_or(0.0), row.verging_gaze_error_deg);
      if (row.verging_gaze_error_deg > settings.off_target_deg) {
        score.off_target_s += row_duration_s(rows, k);
        stretch_s += row_duration_s(rows, k);
        score.longest_off_target_s = std::max(score.longest_off_target_s, stretch_s);
      } else {
        stretch_s = 0.0;
      }
    }
  }
  score.verged_at_s = held_from;
  if (last_seen != nullptr) score.final_error_deg = last_seen->verging_gaze_error_deg;
  if (!score.final_error_deg) {
    score.failure = "the verging eye's target was never seen";
    return score;
  }

  const double within_s = run.task == GazeBenchTask::kSaccadeDepth ? settings.reverge_within_s
                                                                   : settings.verge_within_s;
  if (!score.verged_at_s) {
    score.failure =
        describe("not verged at the end: true verging error %.2f deg", *score.final_error_deg);
  } else if (run.task == GazeBenchTask::kDistractors) {
    if (!score.first_verged_s || *score.first_verged_s > within_s) {
      score.failure = describe("first verged after %.2f s", score.first_verged_s.value_or(-1.0));
    } else if (score.longest_off_target_s >
               settings.max_off_target_s + 0.01 * row_duration_s(rows, rows.size() - 1)) {
      // The stretch is a sum of row durations: 20 rows of 5 ms may add to 0.1 + 1e-16.
      score.failure = describe("%.3f s off the target in one stretch while it was visible",
                               score.longest_off_target_s);
    }
  } else if (*score.verged_at_s > within_s) {
    score.failure = describe("verged (and held) only after %.2f s", *score.verged_at_s);
  }
  score.success = score.failure.empty();
  return score;
}

}  // namespace cambio::app
