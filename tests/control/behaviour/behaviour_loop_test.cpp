// The behaviour loop on the shipped rig: the Observation it builds (the dominant eye's believed
// pose against a closed form, the channels' values) and what it does when a behaviour throws.
#include "cambio/behaviour/behaviour_loop.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "recording_actions.hpp"

#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"

namespace cambio::behaviour {
namespace {

hal::HardwareInfo shipped_rig() {
  return config::hardware_description(
      config::load_rig(config::find_shipped_config("rigs/cambio.yaml")));
}

using testing::RecordingActions;

// Keeps what it saw; throws at the step it is told to.
class Watcher final : public Behaviour {
 public:
  int throw_at_step = -1;
  int starts = 0;
  int steps = 0;
  Eigen::Vector3d axis_W = Eigen::Vector3d::Zero();
  std::uint64_t ssm_sequence = 0;
  bool saw_gaze = false;
  std::vector<std::string> maps;
  void start(const Observation& o, Actions&) override {
    ++starts;
    record(o);
  }
  void step(const Observation& o, Actions&) override {
    if (++steps == throw_at_step) throw std::runtime_error("lost track");
    record(o);
  }
  std::string status() const override { return "watched " + std::to_string(steps); }

 private:
  void record(const Observation& o) {
    axis_W = o.X_W_dominant_camera.linear().col(2);
    ssm_sequence = o.ssm != nullptr ? o.ssm->sequence : 0;
    saw_gaze = o.gaze != nullptr;
    maps.assign(o.feature_map_names.begin(), o.feature_map_names.end());
  }
};

struct Rig {
  hal::HardwareInfo hardware = shipped_rig();
  hal::SeqlockChannel<perception::SsmSummary> ssm;
  hal::SeqlockChannel<control::GazeStatus> gaze;
  hal::SeqlockChannel<control::JointStateFrame> states;
  std::vector<std::string> rig_order;
  Rig() {
    for (const auto& group : hardware.groups) {
      rig_order.insert(rig_order.end(), group.joints.begin(), group.joints.end());
    }
  }
  control::BelievedJoints believed() {
    std::vector<int> indices(rig_order.size());
    for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = static_cast<int>(i);
    return control::BelievedJoints({{&states, indices}}, static_cast<int>(rig_order.size()));
  }
  void publish_joints(const std::string& joint, double position_rad) {
    control::JointStateFrame frame;
    frame.count = static_cast<int>(rig_order.size());
    for (std::size_t i = 0; i < rig_order.size(); ++i) {
      frame.states[i].position_rad = rig_order[i] == joint ? position_rad : 0.0;
    }
    states.write(frame);
  }
};

hal::LoopTick tick_at(std::uint64_t cycle) {
  const auto now_ns = static_cast<std::int64_t>(cycle) * 100'000'000;
  return {cycle, now_ns, now_ns, 0.1};
}

TEST(BehaviourLoopTest, ObservesTheChannelsAndTheDominantEyesBelievedPose) {
  Rig rig;
  Watcher watcher;
  RecordingActions actions;
  BehaviourLoopSources sources{&rig.ssm, {}, &rig.gaze, nullptr, {"intensity", "log@1.4"}};
  BehaviourLoop loop("behaviour", rig.hardware, hal::Eye::kLeft, sources, rig.believed(), watcher,
                     actions);
  const std::string pan = rig.hardware.find_camera(rig.hardware.stereo->left_camera)->parent_frame;
  rig.publish_joints(pan, 0.0);
  loop.configure();
  loop.activate();
  ASSERT_EQ(loop.update(tick_at(0)), hal::Status::kOk);
  EXPECT_EQ(watcher.starts, 1);
  EXPECT_FALSE(watcher.saw_gaze);  // Nothing published yet.
  const Eigen::Vector3d axis_at_zero = watcher.axis_W;

  perception::SsmSummary summary;
  summary.sequence = 42;
  rig.ssm.write(summary);
  rig.gaze.write(control::GazeStatus{});
  rig.publish_joints(pan, 0.2);
  ASSERT_EQ(loop.update(tick_at(1)), hal::Status::kOk);
  EXPECT_EQ(watcher.steps, 1);
  EXPECT_EQ(watcher.ssm_sequence, 42u);
  EXPECT_TRUE(watcher.saw_gaze);
  EXPECT_EQ(watcher.maps, (std::vector<std::string>{"intensity", "log@1.4"}));
  // The eye pans about its vertical axis with the neck and eye tilt at zero: the optical axis
  // turns by the pan angle, to the robot's left (+y) for a positive pan.
  EXPECT_NEAR(std::acos(std::clamp(axis_at_zero.dot(watcher.axis_W), -1.0, 1.0)), 0.2, 1e-9);
  EXPECT_GT(watcher.axis_W.y(), axis_at_zero.y());
  EXPECT_EQ(loop.status(), "watched 1");
  EXPECT_TRUE(loop.allocates_in_update());
}

TEST(BehaviourLoopTest, ABehaviourThatThrowsIsStoppedHoldingAndTheErrorKept) {
  Rig rig;
  Watcher watcher;
  watcher.throw_at_step = 3;
  RecordingActions actions;
  BehaviourLoop loop("behaviour", rig.hardware, hal::Eye::kLeft,
                     BehaviourLoopSources{&rig.ssm, {}, &rig.gaze, nullptr, {}}, rig.believed(),
                     watcher, actions);
  loop.activate();
  std::vector<hal::Status> statuses;
  for (std::uint64_t cycle = 0; cycle < 8; ++cycle) statuses.push_back(loop.update(tick_at(cycle)));
  EXPECT_EQ(statuses[3], hal::Status::kFault);
  EXPECT_EQ(statuses[4], hal::Status::kOk);
  EXPECT_EQ(watcher.steps, 3);  // Never called again after it threw.
  EXPECT_EQ(actions.holds, 1);
  EXPECT_TRUE(loop.failed());
  EXPECT_EQ(loop.error(), "the behaviour's step() threw: lost track");
  EXPECT_EQ(loop.fault_message(), loop.error());
  EXPECT_EQ(loop.status(), "stopped: the behaviour's step() threw: lost track");
}

}  // namespace
}  // namespace cambio::behaviour
