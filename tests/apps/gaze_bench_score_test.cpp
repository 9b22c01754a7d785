#include <gtest/gtest.h>

#include <vector>

#include "gaze_bench_score.hpp"

// The distractors goal as the gaze-bench states it: never more than 100 ms verged on a surface
// other than the target (outside occlusions). Rows are a control cycle of 5 ms; the verging
// eye's true error is all the scorer reads here.

namespace cambio::app {
namespace {

constexpr double kRowS = 0.005;

struct Stretch {
  int rows;
  double verging_error_deg;
  bool occluded = false;
};

Trace trace_of(const std::vector<Stretch>& stretches) {
  Trace trace;
  double t = 0.0;
  for (const Stretch& stretch : stretches) {
    for (int k = 0; k < stretch.rows; ++k) {
      TraceRow row;
      row.time_s = t;
      row.verging_gaze_error_deg = stretch.verging_error_deg;
      row.dominant_gaze_error_deg = 0.01;
      row.target_occluded = stretch.occluded;
      trace.rows.push_back(row);
      t += kRowS;  // Summed, as a recorder's clock reads: 0.1 s is not exactly 20 rows of 5 ms.
    }
  }
  return trace;
}

GeneratedGazeRun distractors_run() {
  GeneratedGazeRun run;
  run.task = GazeBenchTask::kDistractors;
  return run;
}

TEST(GazeBenchScore, TwoStretchesOfAHundredMillisecondsOffTheTargetMeetTheDistractorsGoal) {
  const GazeRunScore score = score_gaze_run(
      distractors_run(), trace_of({{40, 0.05}, {20, 2.0}, {60, 0.05}, {20, 2.0}, {60, 0.05}}));
  EXPECT_TRUE(score.success) << score.failure;
  EXPECT_NEAR(score.longest_off_target_s, 0.1, 1e-9);
  EXPECT_NEAR(score.off_target_s, 0.2, 1e-9);  // Reported in total as well.
}

TEST(GazeBenchScore, ARowMoreThanAHundredMillisecondsInOneStretchFailsIt) {
  const GazeRunScore score =
      score_gaze_run(distractors_run(), trace_of({{40, 0.05}, {21, 2.0}, {60, 0.05}}));
  EXPECT_FALSE(score.success);
  EXPECT_NEAR(score.longest_off_target_s, 0.105, 1e-9);
  EXPECT_EQ(score.failure, "0.105 s off the target in one stretch while it was visible");
}

TEST(GazeBenchScore, AnOcclusionNeitherAddsToAStretchNorEndsIt) {
  const GazeRunScore score = score_gaze_run(
      distractors_run(), trace_of({{40, 0.05}, {15, 2.0}, {30, 2.0, true}, {15, 2.0}, {60, 0.05}}));
  EXPECT_FALSE(score.success);
  EXPECT_NEAR(score.longest_off_target_s, 0.15, 1e-9);
  EXPECT_NEAR(score.occluded_s, 0.15, 1e-9);
}

}  // namespace
}  // namespace cambio::app
