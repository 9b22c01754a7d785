// The experiment metrics on synthetic traces whose answers are known in closed form.

#include "run_metrics.hpp"

#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace cambio::app {
namespace {

constexpr double kDt = 0.005;  // 200 Hz, the control rate.
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

/// A trace of `duration_s` at kDt over two eye pan joints (dominant = 0, verging = 1), with
/// every row filled by `fill(t, row, joints)`.
Trace make_trace(
    double duration_s,
    const std::function<void(double, TraceRow&, std::vector<TraceJointSample>&)>& fill) {
  Trace trace;
  trace.joint_names = {"left_eye_pan", "right_eye_pan"};
  trace.dominant_pan_joint = 0;
  trace.verging_pan_joint = 1;
  const int rows = static_cast<int>(std::lround(duration_s / kDt)) + 1;
  for (int k = 0; k < rows; ++k) {
    const double t = k * kDt;
    TraceRow row;
    row.time_s = t;
    row.gaze_status = true;
    std::vector<TraceJointSample> joints(2, TraceJointSample{0.0, 0.0, 0.0});
    fill(t, row, joints);
    trace.add_row(row, joints);
  }
  return trace;
}

/// The first sample time at or after t (the trace's grid).
double on_grid_after(double t) {
  return std::ceil(t / kDt - 1e-9) * kDt;
}

void set_errors(TraceRow& row, double dominant_deg, double verging_deg) {
  row.dominant_gaze_error_deg = dominant_deg;
  row.verging_gaze_error_deg = verging_deg;
  row.true_gaze_error_deg = std::max(dominant_deg, verging_deg);
}

void set_disparity(TraceRow& row, double disparity_px) {
  row.disparity_valid = true;
  row.disparity_px = disparity_px;
  row.disparity_confidence = 0.9;
}

TEST(RunMetricsTest, SettleTimeIsWhenBothThresholdsHoldToTheEnd) {
  // After a fixate command at 0.2 s: disparity -5 exp(-t'/0.1) px and gaze error
  // 2 exp(-t'/0.15) deg. |d| <= 0.5 from t' = 0.1 ln 10 = 0.230 s, the error <= 0.1 deg from
  // t' = 0.15 ln 20 = 0.449 s: the later one is the settle time (on the sample grid).
  const double t_command = 0.2;
  const Trace trace = make_trace(2.0, [&](double t, TraceRow& row, auto&) {
    const double since = std::max(0.0, t - t_command);
    set_disparity(row, -5.0 * std::exp(-since / 0.1));
    set_errors(row, 2.0 * std::exp(-since / 0.15), 0.5 * 2.0 * std::exp(-since / 0.15));
  });
  MetricInputs inputs;
  inputs.commands = {{0.0, control::GazeAction::kHold}, {t_command, control::GazeAction::kFixate}};
  const RunMetrics metrics = compute_metrics(trace, inputs);
  const double expected = on_grid_after(t_command + 0.15 * std::log(20.0)) - t_command;
  ASSERT_TRUE(metrics.find("settle_time_s"));
  EXPECT_NEAR(*metrics.find("settle_time_s"), expected, 1e-9);
  EXPECT_NEAR(*metrics.find("final_disparity_px"), 5.0 * std::exp(-1.8 / 0.1), 1e-12);
  EXPECT_NEAR(*metrics.find("true_gaze_error_deg"), 2.0 * std::exp(-1.8 / 0.15), 1e-12);
  // The first row meeting both thresholds is the settle time itself: the verging error from
  // there is the verging error at it (a decaying curve's first value).
  EXPECT_NEAR(*metrics.find("max_verging_gaze_error_visible_deg"), std::exp(-(expected) / 0.15),
              1e-9);
}

TEST(RunMetricsTest, AnExcursionLateInTheRunMovesTheSettleTime) {
  // Settled from 0.5 s, then an invalid disparity at 1.2 s: the gaze settled again only after.
  const Trace trace = make_trace(2.0, [&](double t, TraceRow& row, auto&) {
    set_errors(row, t < 0.5 ? 1.0 : 0.01, 0.0);
    set_disparity(row, t < 0.5 ? 3.0 : 0.1);
    if (std::abs(t - 1.2) < 1e-9) row.disparity_valid = false;
  });
  const RunMetrics metrics = compute_metrics(trace, {});
  EXPECT_NEAR(*metrics.find("settle_time_s"), 1.2 + kDt, 1e-9);
}

TEST(RunMetricsTest, AGazeThatNeverSettlesHasNoSettleTimeAndItsGoalFailsWithTheReason) {
  const Trace trace = make_trace(1.0, [&](double, TraceRow& row, auto&) {
    set_errors(row, 0.3, 0.3);
    set_disparity(row, 0.2);
  });
  const RunMetrics metrics = compute_metrics(trace, {});
  EXPECT_FALSE(metrics.find("settle_time_s"));
  EXPECT_NE(metrics.absent_reason("settle_time_s").find("never settled"), std::string::npos);
  const std::vector<Goal> goals = {{"settle_time_s", GoalBound::kMax, 1.0}};
  const auto results = evaluate_goals(metrics, goals);
  ASSERT_EQ(results.size(), 1u);
  EXPECT_FALSE(results[0].passed);
  EXPECT_NE(results[0].reason.find("never settled"), std::string::npos);
  EXPECT_FALSE(all_passed(results));
}

/// A saccade of 0.5 rad of the dominant pan at 20 rad/s^2 (a triangle: duration 2 sqrt(0.5/20)
/// s), commanded at 1.0 s and started by the loop 10 ms later; the verging eye's error rises to
/// 3 deg (a half sine) while it moves; the disparity is invalid while moving and decays as
/// 8 exp(-t'/0.05) px after the stop.
struct SaccadeCase {
  static constexpr double kCommand_s = 1.0;
  static constexpr double kStart_s = 1.01;
  static constexpr double kAmplitude_rad = 0.5;
  static constexpr double kAcceleration_rad_s2 = 20.0;
  static double duration_s() { return 2.0 * std::sqrt(kAmplitude_rad / kAcceleration_rad_s2); }
  static double pan_rad(double t) {
    const double s = std::clamp(t - kStart_s, 0.0, duration_s());
    const double half = duration_s() / 2;
    if (s <= half) return 0.5 * kAcceleration_rad_s2 * s * s;
    const double r = duration_s() - s;
    return kAmplitude_rad - 0.5 * kAcceleration_rad_s2 * r * r;
  }
  static double stop_s() { return on_grid_after(kStart_s + duration_s()); }

  static Trace trace(bool report_saccade_active) {
    return make_trace(2.0, [&](double t, TraceRow& row, std::vector<TraceJointSample>& joints) {
      joints[0].true_rad = pan_rad(t);
      joints[1].true_rad = pan_rad(t) + 0.1;
      const bool moving = t >= kStart_s && t < kStart_s + duration_s();
      row.saccade_active = report_saccade_active && moving;
      const double verging =
          moving ? 3.0 * std::sin(std::numbers::pi * (t - kStart_s) / duration_s()) : 0.05;
      set_errors(row, 0.02, verging);
      if (t < kCommand_s) {
        set_disparity(row, 0.1);
      } else if (t >= kStart_s + duration_s()) {
        set_disparity(row, 8.0 * std::exp(-(t - (kStart_s + duration_s())) / 0.05));
      }
    });
  }
};

TEST(RunMetricsTest, SaccadeDurationVergenceLossAndReverge) {
  MetricInputs inputs;
  inputs.commands = {{0.0, control::GazeAction::kFixate},
                     {SaccadeCase::kCommand_s, control::GazeAction::kSaccade}};
  const RunMetrics metrics = compute_metrics(SaccadeCase::trace(true), inputs);
  ASSERT_TRUE(metrics.find("saccade_duration_s")) << metrics.absent_reason("saccade_duration_s");
  // The first sample after the motion ends, measured from the command.
  EXPECT_NEAR(*metrics.find("saccade_duration_s"), SaccadeCase::stop_s() - SaccadeCase::kCommand_s,
              1e-9);
  // The half sine's peak, sampled every 5 ms over 0.316 s: within 3 (1 - cos(pi 5/316)).
  EXPECT_NEAR(*metrics.find("max_vergence_error_during_saccade_deg"), 3.0, 0.004);
  // 8 exp(-x / 0.05) <= 1 from x = 0.05 ln 8, on the grid after the stop.
  const double end_s = SaccadeCase::kStart_s + SaccadeCase::duration_s();
  EXPECT_NEAR(*metrics.find("reverge_time_s"),
              on_grid_after(end_s + 0.05 * std::log(8.0)) - SaccadeCase::stop_s(), 1e-9);
  EXPECT_FALSE(metrics.find("pursuit_rms_error_deg"));
}

TEST(RunMetricsTest, SaccadeWithoutAGazeStatusEndsWhenThePanStops) {
  MetricInputs inputs;
  inputs.commands = {{SaccadeCase::kCommand_s, control::GazeAction::kSaccade}};
  const RunMetrics metrics = compute_metrics(SaccadeCase::trace(false), inputs);
  ASSERT_TRUE(metrics.find("saccade_duration_s")) << metrics.absent_reason("saccade_duration_s");
  // The pan's speed falls below 0.05 rad/s once the remaining triangle is shorter than
  // 0.05 / 20 s; by the backward difference, within one sample of the true stop.
  EXPECT_NEAR(*metrics.find("saccade_duration_s"), SaccadeCase::stop_s() - SaccadeCase::kCommand_s,
              kDt + 1e-9);
}

TEST(RunMetricsTest, ASaccadeThatNeverStartsHasNoSaccadeMetrics) {
  const Trace trace =
      make_trace(1.0, [&](double, TraceRow& row, auto&) { set_errors(row, 0.01, 0.01); });
  MetricInputs inputs;
  inputs.commands = {{0.5, control::GazeAction::kSaccade}};
  const RunMetrics metrics = compute_metrics(trace, inputs);
  EXPECT_FALSE(metrics.find("saccade_duration_s"));
  EXPECT_FALSE(metrics.find("reverge_time_s"));
  EXPECT_NE(metrics.absent_reason("reverge_time_s").find("never moved"), std::string::npos);
}

TEST(RunMetricsTest, PursuitRmsIsOverThePursuitAfterItsCatchUp) {
  // 5 deg before the catch-up, A |sin(2 pi 2 t)| for three whole periods (RMS A / sqrt 2), then
  // 10 deg after the next command: only the middle counts.
  const double amplitude = 0.4;
  const Trace trace = make_trace(4.0, [&](double t, TraceRow& row, auto&) {
    double e = 5.0;
    if (t >= 1.5 && t < 3.0) e = amplitude * std::abs(std::sin(2 * std::numbers::pi * 2.0 * t));
    if (t >= 3.0) e = 10.0;
    set_errors(row, e, 0.0);
  });
  MetricInputs inputs;
  inputs.commands = {{1.0, control::GazeAction::kPursue}, {3.0, control::GazeAction::kHold}};
  const RunMetrics metrics = compute_metrics(trace, inputs);
  ASSERT_TRUE(metrics.find("pursuit_rms_error_deg"));
  EXPECT_NEAR(*metrics.find("pursuit_rms_error_deg"), amplitude / std::sqrt(2.0), 1e-9);
  inputs.pursuit_catch_up_s = 0.0;
  // With no catch-up the 5 deg half second counts: sqrt((100 x 25 + 300 A^2/2) / 400).
  EXPECT_NEAR(*compute_metrics(trace, inputs).find("pursuit_rms_error_deg"),
              std::sqrt((100 * 25.0 + 300 * amplitude * amplitude / 2) / 400), 1e-9);
}

TEST(RunMetricsTest, BelievedAgainstTrueJointsFixationAndEyePans) {
  const Trace trace = make_trace(1.0, [&](double t, TraceRow& row, auto& joints) {
    joints[0] = {0.1, 0.1 + 0.002 * t, 0.1};  // Believed drifts to 2 mrad at the end.
    joints[1] = {-0.4, -0.4, -0.4 - 0.001};   // 1 mrad throughout.
    row.fixation_error_m = t < 0.5 ? 0.01 * t : 0.001;
    set_errors(row, 0.0, 0.0);
  });
  const RunMetrics metrics = compute_metrics(trace, {});
  EXPECT_NEAR(*metrics.find("max_believed_vs_true_joint_error_rad"), 0.002, 1e-12);
  EXPECT_NEAR(*metrics.find("final_believed_vs_true_fixation_error_m"), 0.001, 1e-12);
  EXPECT_NEAR(*metrics.find("max_believed_vs_true_fixation_error_m"), 0.01 * 0.495, 1e-12);
  EXPECT_NEAR(*metrics.find("final_max_abs_eye_pan_deg"), 0.401 * kDegPerRad, 1e-9);
}

TEST(RunMetricsTest, OccludedSamplesAreTimedAndLeftOutOfTheVisibleError) {
  // Settled from the start; a distractor hides the target for [1.0, 1.4) with 5 deg of verging
  // error; visible, the verging error peaks at 0.3 deg at 1.6 s.
  const Trace trace = make_trace(2.0, [&](double t, TraceRow& row, auto&) {
    const bool hidden = t >= 1.0 - 1e-9 && t < 1.4 - 1e-9;
    row.target_occluded = hidden;
    double verging = hidden ? 5.0 : 0.05;
    if (std::abs(t - 1.6) < 1e-9) verging = 0.3;
    set_errors(row, 0.01, verging);
    set_disparity(row, 0.1);
  });
  const RunMetrics metrics = compute_metrics(trace, {});
  EXPECT_NEAR(*metrics.find("target_occluded_s"), 0.4, 1e-9);
  EXPECT_NEAR(*metrics.find("max_verging_gaze_error_visible_deg"), 0.3, 1e-12);
}

TEST(RunMetricsTest, MetricsThatDoNotApplyAreAbsentWithAReason) {
  const Trace trace = make_trace(0.5, [&](double, TraceRow&, auto&) {});
  const RunMetrics metrics = compute_metrics(trace, {});
  for (const char* name :
       {"final_disparity_px", "true_gaze_error_deg", "settle_time_s", "saccade_duration_s",
        "pursuit_rms_error_deg", "target_occluded_s", "final_believed_vs_true_fixation_error_m"}) {
    EXPECT_FALSE(metrics.find(name)) << name;
    EXPECT_FALSE(metrics.absent_reason(name).empty()) << name;
  }
  EXPECT_TRUE(metrics.find("final_max_abs_eye_pan_deg"));
  EXPECT_EQ(metrics.values.size() + metrics.absent.size(), std::size(kMetricNames));
  EXPECT_FALSE(compute_metrics(Trace{}, {}).find("final_max_abs_eye_pan_deg"));
}

TEST(RunMetricsTest, AnObjectIsVisitedOnceTheAxisRestsOnItOutsideSaccadesForTheDwell) {
  // 0-0.3 s: a saccade across `a` (not a visit); 0.3-0.6 s: resting on `a` (visited once 0.2 s
  // have passed, at 0.5 s); 0.6-0.7 s: on `b` for 0.1 s only; then on nothing; 1.0-1.4 s on `b`
  // again (visited at 1.2 s); `c` is never met.
  Trace trace = make_trace(1.5, [&](double t, TraceRow& row, auto&) {
    const auto during = [&](double from, double to) { return t >= from - 1e-9 && t < to - 1e-9; };
    row.saccade_active = during(0.0, 0.3);
    if (during(0.0, 0.6)) row.axis_object = 0;
    if (during(0.6, 0.7) || during(1.0, 1.4)) row.axis_object = 1;
  });
  trace.visit_objects = {"a", "b", "c"};
  const auto visits = object_visit_times(trace, 0.2);
  ASSERT_EQ(visits.size(), 3u);
  ASSERT_TRUE(visits[0] && visits[1]);
  EXPECT_NEAR(*visits[0], 0.5, 1e-9);
  EXPECT_NEAR(*visits[1], 1.2, 1e-9);
  EXPECT_FALSE(visits[2]);
  MetricInputs inputs;
  inputs.visit_dwell_s = 0.2;
  RunMetrics metrics = compute_metrics(trace, inputs);
  EXPECT_EQ(*metrics.find("objects_visited"), 2.0);
  EXPECT_EQ(metrics.absent_reason("all_objects_visited_s"), "never visited: c");
  trace.visit_objects = {"a", "b"};
  metrics = compute_metrics(trace, inputs);
  EXPECT_NEAR(*metrics.find("all_objects_visited_s"), 1.2, 1e-9);
}

TEST(RunMetricsTest, RefusesCommandsOutOfOrderAndBadThresholds) {
  const Trace trace = make_trace(0.1, [&](double, TraceRow&, auto&) {});
  MetricInputs inputs;
  inputs.commands = {{1.0, control::GazeAction::kFixate}, {0.5, control::GazeAction::kSaccade}};
  EXPECT_THROW(compute_metrics(trace, inputs), std::invalid_argument);
  inputs.commands.clear();
  inputs.settle_disparity_px = 0.0;
  EXPECT_THROW(compute_metrics(trace, inputs), std::invalid_argument);
}

TEST(RunMetricsTest, GoalsPassOnTheirBoundAndFailBeyondIt) {
  RunMetrics metrics;
  metrics.values = {{"final_disparity_px", 0.5}, {"target_occluded_s", 0.2}};
  metrics.absent = {{"reverge_time_s", "the run sent no saccade command"}};
  const std::vector<Goal> goals = {{"final_disparity_px", GoalBound::kMax, 0.5},
                                   {"target_occluded_s", GoalBound::kMin, 0.1},
                                   {"target_occluded_s", GoalBound::kMax, 0.15},
                                   {"reverge_time_s", GoalBound::kMax, 0.3}};
  const auto results = evaluate_goals(metrics, goals);
  ASSERT_EQ(results.size(), 4u);
  EXPECT_TRUE(results[0].passed) << "a value on its bound passes";
  EXPECT_TRUE(results[1].passed);
  EXPECT_FALSE(results[2].passed);
  EXPECT_EQ(results[2].reason, "above the maximum");
  EXPECT_FALSE(results[3].passed);
  EXPECT_EQ(results[3].reason, "absent: the run sent no saccade command");
  EXPECT_FALSE(all_passed(results));
  EXPECT_TRUE(all_passed(std::span(results).first(2)));

  const Json json = goals_json(results);
  EXPECT_EQ(json["final_disparity_px"]["max"], 0.5);
  EXPECT_EQ(json["final_disparity_px"]["value"], 0.5);
  EXPECT_EQ(json["final_disparity_px"]["passed"], true);
  EXPECT_FALSE(json["final_disparity_px"].contains("reason"));
  // Two goals on one metric: one object with both bounds, failed when either fails.
  EXPECT_EQ(json["target_occluded_s"]["min"], 0.1);
  EXPECT_EQ(json["target_occluded_s"]["max"], 0.15);
  EXPECT_EQ(json["target_occluded_s"]["passed"], false);
  EXPECT_TRUE(json["reverge_time_s"]["value"].is_null());
  EXPECT_EQ(json["reverge_time_s"]["passed"], false);
}

TEST(RunMetricsTest, JsonBlocksListMetricsInOrderAndTheLastJoints) {
  const Trace trace = make_trace(0.1, [&](double t, TraceRow& row, auto& joints) {
    joints[0] = {0.2, 0.2 + t, 0.25};
    joints[1] = {kNoValue, -0.1, -0.1};
    set_errors(row, 0.5, 0.25);
    set_disparity(row, -2.0);
  });
  const RunMetrics metrics = compute_metrics(trace, {});
  const Json json = metrics_json(metrics);
  std::vector<std::string> keys;
  for (const auto& item : json.items()) keys.push_back(item.key());
  ASSERT_GE(keys.size(), 3u);
  EXPECT_EQ(keys[0], "final_disparity_px");
  EXPECT_EQ(keys[1], "true_gaze_error_deg");
  EXPECT_EQ(json["final_disparity_px"], 2.0);
  EXPECT_EQ(json["true_gaze_error_deg"], 0.5);
  const Json joints = final_joints_json(trace);
  EXPECT_NEAR(joints["left_eye_pan"]["believed_rad"].get<double>(), 0.3, 1e-12);
  EXPECT_EQ(joints["left_eye_pan"]["true_rad"], 0.25);
  EXPECT_EQ(joints["left_eye_pan"]["command_rad"], 0.2);
  EXPECT_TRUE(joints["right_eye_pan"]["command_rad"].is_null());
}

TEST(TraceCsvTest, HeaderNamesUnitsAndEveryRowHasItsColumns) {
  Trace trace = make_trace(0.01, [&](double, TraceRow& row, auto& joints) {
    joints[0] = {0.5, 0.25, 0.125};
    set_errors(row, 1.5, 0.5);
    row.action = control::GazeAction::kSaccade;
  });
  const std::string csv = trace_csv(trace);
  std::istringstream lines(csv);
  std::string header, first;
  std::getline(lines, header);
  std::getline(lines, first);
  EXPECT_EQ(header.rfind("time_s,left_eye_pan_command_rad,left_eye_pan_believed_rad,"
                         "left_eye_pan_true_rad,right_eye_pan_command_rad",
                         0),
            0u);
  const auto columns = [](const std::string& line) {
    return std::count(line.begin(), line.end(), ',') + 1;
  };
  EXPECT_EQ(columns(header), columns(first));
  EXPECT_EQ(first.rfind("0,0.5,0.25,0.125,0,0,0,nan,0,0,saccade,0,nan,nan,nan,1.5,0.5,1.5,0", 0),
            0u)
      << first;
  std::size_t data_rows = 0;
  for (std::string line; std::getline(lines, line);) ++data_rows;
  EXPECT_EQ(data_rows + 1, trace.rows.size());
  EXPECT_THROW(trace.add_row(TraceRow{}, std::vector<TraceJointSample>(1)), std::invalid_argument);
}

TEST(RunMetricsTest, TheReachIsScoredFromTheTracesReachRecord) {
  Trace trace = make_trace(0.1, [&](double, TraceRow&, auto&) {});
  trace.reach.accepted = true;
  trace.reach.command_s = 1.0;
  trace.reach.touch_s = 2.25;
  trace.reach.touch_position_error_m = 0.002;
  trace.reach.estimated_target_error_m = 0.004;
  trace.reach.final_phase = control::ReachPhase::kTouching;
  RunMetrics metrics = compute_metrics(trace, {});
  EXPECT_DOUBLE_EQ(*metrics.find("time_to_touch_s"), 1.25);
  EXPECT_DOUBLE_EQ(*metrics.find("touch_position_error_m"), 0.002);
  EXPECT_DOUBLE_EQ(*metrics.find("estimated_target_error_m"), 0.004);

  // Arrived without a touch: the estimate is scored, the touch is absent and says how it ended.
  trace.reach.touch_s = kNoValue;
  trace.reach.final_phase = control::ReachPhase::kArrived;
  metrics = compute_metrics(trace, {});
  EXPECT_FALSE(metrics.find("time_to_touch_s"));
  EXPECT_EQ(metrics.absent_reason("time_to_touch_s"),
            "the gripper never touched (the reach ended arrived)");
  EXPECT_TRUE(metrics.find("estimated_target_error_m"));

  // Refused: every reach metric is absent with the arms' reason, and a goal on it fails.
  trace.reach = ReachRecord{};
  trace.reach.refused = true;
  trace.reach.refusal = "out of reach: the target is 0.972 m from right_arm's shoulder";
  metrics = compute_metrics(trace, {});
  for (const char* name :
       {"time_to_touch_s", "touch_position_error_m", "estimated_target_error_m"}) {
    EXPECT_EQ(metrics.absent_reason(name),
              "the reach was refused: out of reach: the target is 0.972 m from right_arm's "
              "shoulder")
        << name;
  }
  const std::vector<Goal> goals{{"time_to_touch_s", GoalBound::kMax, 3.0}};
  const auto results = evaluate_goals(metrics, goals);
  EXPECT_FALSE(results[0].passed);
  EXPECT_EQ(metrics.absent_reason("time_to_touch_s").empty(), false);
  EXPECT_EQ(compute_metrics(make_trace(0.1, [&](double, TraceRow&, auto&) {}), {})
                .absent_reason("time_to_touch_s"),
            "the run made no reach");
}

}  // namespace
}  // namespace cambio::app
