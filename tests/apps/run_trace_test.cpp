// The trace recorder on a sim world whose true gaze errors are known in closed form: the head at
// zero puts the left eye's optical centre at (0.06, 0.06, 1.40) and the right eye's at
// (0.06, -0.06, 1.40), both looking along +x.

#include "run_trace.hpp"

#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>

#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/sim/sim_backend.hpp"

namespace cambio::app {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr std::int64_t kPeriodNs = 5'000'000;

/// A ball on the left eye's axis at 1 m; optionally a small ball hiding the point where that
/// axis meets the big one (x = 0.9) from the right eye.
config::SceneConfig scene(bool blocker) {
  std::string yaml = R"(
world: {floor: false}
objects:
  - {name: ball, shape: sphere, radius_m: 0.10, xyz_m: [1.0, 0.06, 1.40], rgb: [1, 0, 0]}
)";
  if (blocker) {
    // The right eye's sight line to (0.9, 0.06, 1.40) crosses x = 0.5 at y = 0.0029; the left
    // eye's axis (y = 0.06) passes 0.057 m from this ball's centre, outside its 0.03 m radius.
    yaml += "  - {name: blocker, shape: sphere, radius_m: 0.03, xyz_m: [0.5, 0.003, 1.40]}\n";
  }
  return config::load_scene_from_string(yaml, "trace_scene.yaml");
}

class TraceRecorderTest : public ::testing::Test {
 protected:
  void build(bool blocker) {
    rig_ = config::load_rig(config::find_shipped_config("rigs/cambio.yaml"));
    for (auto& camera : rig_.cameras) {  // Small key frames keep the test quick.
      camera.width_px = 160;
      camera.height_px = 120;
      camera.focal_x_px = camera.focal_y_px = 138.564;
      camera.principal_x_px = 79.5;
      camera.principal_y_px = 59.5;
    }
    sim_ = std::make_unique<sim::SimBackend>(
        rig_, scene(blocker), config::hardware_description(rig_), hal::BackendContext{&clock_});
    for (const auto& group : rig_.groups) {
      for (const auto& joint : group.joints) names_.push_back(joint);
    }
  }

  TraceSources sources() {
    TraceSources s;
    s.joint_names = names_;
    s.targets = &targets_;
    s.believed = {{&head_states_, {0, 1, 2, 3, 4}}};
    s.gaze = &gaze_;
    s.truth = &sim_->ground_truth();
    s.dominant_camera = "left_eye";
    s.verging_camera = "right_eye";
    s.dominant_pan_joint = "left_eye_pan";
    s.verging_pan_joint = "right_eye_pan";
    s.target_object = "ball";
    return s;
  }

  void publish(const Eigen::Vector3d& target_W) {
    control::JointTargetFrame targets;
    targets.count = static_cast<int>(names_.size());
    targets.commands[3] = {hal::CommandMode::kPosition, 0.25, 0, 0};
    targets.commands[4] = {hal::CommandMode::kVelocity, 0.1, 0, 0};
    targets_.write(targets);
    control::JointStateFrame states;
    states.count = 5;
    for (int i = 0; i < 5; ++i) states.states[i].position_rad = 0.01 * (i + 1);
    head_states_.write(states);
    control::GazeStatus status;
    status.action = control::GazeAction::kFixate;
    status.target_set = true;
    status.target_W_m = {target_W.x(), target_W.y(), target_W.z()};
    status.believed_fixation_valid = true;
    status.believed_fixation_W_m = {1.0, 0.0, 1.40};
    status.disparity_valid = true;
    status.disparity_px = -3.5;
    status.disparity_confidence = 0.75;
    gaze_.write(status);
  }

  static void run(TraceRecorder& recorder, int cycles) {
    for (int k = 0; k < cycles; ++k) {
      const std::int64_t t = k * kPeriodNs;
      ASSERT_EQ(recorder.update(hal::LoopTick{static_cast<std::uint64_t>(k), t, t, 0.005}),
                hal::Status::kOk)
          << recorder.fault_message();
    }
  }

  hal::ManualClock clock_;
  config::RigConfig rig_;
  std::unique_ptr<sim::SimBackend> sim_;
  std::vector<std::string> names_;
  hal::SeqlockChannel<control::JointTargetFrame> targets_;
  hal::SeqlockChannel<control::JointStateFrame> head_states_;
  hal::SeqlockChannel<control::GazeStatus> gaze_;
};

TEST_F(TraceRecorderTest, ScoresTrueGazeErrorsJointsAndFixationAgainstClosedForm) {
  build(false);
  // The commanded point 0.1 m to the left of the ball's centre: the dominant eye is off it by
  // atan(0.1 / 0.94); the verging eye aims at where the dominant axis meets the ball,
  // (0.9, 0.06, 1.40): off by atan(0.12 / 0.84).
  publish(Eigen::Vector3d(1.0, 0.16, 1.40));
  TraceSources s = sources();
  s.key_frame_times_s = {0.01};
  TraceRecorder recorder(s, 200.0, 1.0);
  recorder.configure();
  run(recorder, 4);
  const Trace& trace = recorder.trace();
  ASSERT_EQ(trace.rows.size(), 4u);
  EXPECT_TRUE(trace.problems.empty()) << trace.problems.front();
  const TraceRow& row = trace.rows[3];
  EXPECT_NEAR(row.time_s, 0.015, 1e-12);
  EXPECT_NEAR(row.dominant_gaze_error_deg, std::atan(0.1 / 0.94) * kDegPerRad, 1e-6);
  EXPECT_NEAR(row.verging_gaze_error_deg, std::atan(0.12 / 0.84) * kDegPerRad, 1e-6);
  EXPECT_DOUBLE_EQ(row.true_gaze_error_deg, row.verging_gaze_error_deg);
  EXPECT_FALSE(row.target_occluded);
  // Parallel axes meet nowhere: no true fixation, no fixation error.
  EXPECT_FALSE(row.true_fixation_valid);
  EXPECT_TRUE(row.believed_fixation_valid);
  EXPECT_TRUE(std::isnan(row.fixation_error_m));
  EXPECT_TRUE(row.disparity_valid);
  EXPECT_EQ(row.disparity_px, -3.5);
  EXPECT_EQ(row.action, control::GazeAction::kFixate);
  // Joints: position commands recorded, velocity commands not; believed from the channel;
  // true from the world (the rig's initial pose, zero for the head).
  const auto joints = trace.joints_at(3);
  EXPECT_EQ(joints[3].command_rad, 0.25);
  EXPECT_TRUE(std::isnan(joints[4].command_rad));
  EXPECT_EQ(joints[4].believed_rad, 0.05);
  EXPECT_TRUE(std::isnan(joints[5].believed_rad)) << "no channel covers the arms";
  EXPECT_EQ(joints[3].true_rad, 0.0);
  EXPECT_EQ(trace.dominant_pan_joint, 3);
  // Both eyes rendered once, at the first sample at or after 0.01 s.
  ASSERT_EQ(trace.key_frames.size(), 2u);
  EXPECT_NEAR(trace.key_frames[0].time_s, 0.01, 1e-12);
  EXPECT_EQ(trace.key_frames[1].camera, "right_eye");
  EXPECT_EQ(trace.key_frames[0].image.width_px, 160);
  EXPECT_EQ(key_frame_file_name(trace.key_frames[0]), "key_10ms_left_eye.png");
}

TEST_F(TraceRecorderTest, PursuitScoresTheObjectAndAnotherObjectOccludesTheVergingEye) {
  build(true);
  publish(Eigen::Vector3d(5.0, 5.0, 5.0));
  control::GazeStatus status;
  gaze_.read(status);
  // Pursuit is scored against the point of the ball the dominant eye's axis met when it began
  // (its front, r = 0.1 m before the centre at x = 1.0 m), not against target_W_m.
  status.action = control::GazeAction::kPursue;
  gaze_.write(status);
  TraceRecorder recorder(sources(), 200.0, 1.0);
  recorder.configure();
  run(recorder, 1);
  const TraceRow& row = recorder.trace().rows.at(0);
  EXPECT_NEAR(row.dominant_gaze_error_deg, 0.0, 1e-6);
  EXPECT_NEAR(row.target_W_m[0], 0.9, 1e-9);
  EXPECT_TRUE(row.target_occluded);
}

TEST_F(TraceRecorderTest, StopsAtItsPreallocatedRowsAndRefusesBadSources) {
  build(false);
  publish(Eigen::Vector3d(1.0, 0.06, 1.40));
  TraceRecorder recorder(sources(), 200.0, 0.01);  // 2 periods + the end sample: 3 rows.
  EXPECT_TRUE(recorder.allocates_in_update());
  recorder.configure();
  run(recorder, 5);
  EXPECT_EQ(recorder.trace().rows.size(), 3u);
  EXPECT_TRUE(recorder.trace().truncated);

  TraceSources bad = sources();
  bad.targets = nullptr;
  EXPECT_THROW(TraceRecorder(bad, 200.0, 1.0), std::invalid_argument);
  bad = sources();
  bad.believed[0].rig_indices = {0, 99};
  EXPECT_THROW(TraceRecorder(bad, 200.0, 1.0), std::invalid_argument);
  bad = sources();
  bad.dominant_pan_joint = "no_such_joint";
  EXPECT_THROW(TraceRecorder(bad, 200.0, 1.0), std::invalid_argument);
  bad = sources();
  bad.target_object = "no_such_object";
  TraceRecorder unknown(bad, 200.0, 1.0);
  EXPECT_THROW(unknown.configure(), std::out_of_range);
}

}  // namespace
}  // namespace cambio::app
