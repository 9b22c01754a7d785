// What behaviours and the console send: every action becomes one command on the loop that
// carries it out, with what was checked first (limits clamped and said, pixels inside the
// image, finite points) and refusals that say why.
#include "robot_actions.hpp"

#include <numbers>

#include <gtest/gtest.h>

#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"

namespace cambio::app {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

class RobotActionsTest : public ::testing::Test {
 protected:
  RobotActionsTest()
      : hardware_(config::hardware_description(
            config::load_rig(config::find_shipped_config("rigs/cambio.yaml")))) {
    for (const auto& group : hardware_.groups) {
      for (const auto& joint : group.joints) setup_.rig_joint_order.push_back(joint);
    }
    setup_.head_joints = {"neck_pan", "neck_tilt", "eye_tilt", "left_eye_pan", "right_eye_pan"};
    setup_.image_width_px = 640;
    setup_.image_height_px = 480;
  }

  int rig_index(const std::string& joint) const {
    const auto& order = setup_.rig_joint_order;
    return static_cast<int>(std::find(order.begin(), order.end(), joint) - order.begin());
  }
  control::GazeCommand gaze() const {
    control::GazeCommand command;
    EXPECT_TRUE(gaze_.read(command));
    return command;
  }
  control::ArmCommand arm() const {
    control::ArmCommand command;
    EXPECT_TRUE(arms_.read(command));
    return command;
  }

  hal::HardwareInfo hardware_;
  RobotActions::Setup setup_;
  hal::SeqlockChannel<control::GazeCommand> gaze_;
  hal::SeqlockChannel<control::ArmCommand> arms_;
  hal::SeqlockChannel<perception::FeatureRequest> features_;
};

TEST_F(RobotActionsTest, GazeActionsBecomeGazeCommandsEachANewSequence) {
  RobotActions actions(hardware_, setup_, {&gaze_, &arms_, &features_});
  EXPECT_TRUE(actions.look_at_pixel(100, 200).sent);
  const control::GazeCommand look = gaze();
  EXPECT_EQ(look.action, control::GazeAction::kFixate);
  EXPECT_EQ(look.target.kind, control::GazeTargetKind::kPixel);
  EXPECT_EQ(look.target.pixel_px[1], 200.0);
  EXPECT_TRUE(look.verge);

  EXPECT_TRUE(actions.saccade_to_point({1.0, 0.2, 1.3}).sent);
  const control::GazeCommand saccade = gaze();
  EXPECT_EQ(saccade.action, control::GazeAction::kSaccade);
  EXPECT_EQ(saccade.target.kind, control::GazeTargetKind::kPoint);
  EXPECT_EQ(saccade.target.point_W_m[1], 0.2);
  EXPECT_GT(saccade.sequence, look.sequence);

  EXPECT_TRUE(actions.saccade_by_angles(10 * kDeg, -5 * kDeg).sent);
  EXPECT_EQ(gaze().target.kind, control::GazeTargetKind::kAngles);
  EXPECT_TRUE(actions.pursue().sent);
  EXPECT_EQ(gaze().action, control::GazeAction::kPursue);
  EXPECT_TRUE(actions.verge(false).sent);
  EXPECT_EQ(gaze().action, control::GazeAction::kVerge);
  EXPECT_FALSE(gaze().verge);
  // Vergence stays off for what follows, until switched on.
  EXPECT_TRUE(actions.hold().sent);
  EXPECT_EQ(gaze().action, control::GazeAction::kHold);
  EXPECT_FALSE(gaze().verge);
  EXPECT_FALSE(actions.verging());
  EXPECT_EQ(actions.gaze_commands_sent(), 6U);
}

TEST_F(RobotActionsTest, ArmActionsBecomeArmCommands) {
  RobotActions actions(hardware_, setup_, {&gaze_, &arms_, &features_});
  EXPECT_TRUE(actions.reach_fixated(control::ArmSide::kNearest).sent);
  EXPECT_EQ(arm().action, control::ArmAction::kReach);
  EXPECT_EQ(arm().target, control::ReachTargetKind::kFixation);
  EXPECT_TRUE(actions.reach_point({0.5, -0.1, 1.0}, control::ArmSide::kRight).sent);
  EXPECT_EQ(arm().target, control::ReachTargetKind::kPoint);
  EXPECT_EQ(arm().arm, control::ArmSide::kRight);
  EXPECT_EQ(arm().point_W_m[2], 1.0);
  const auto huge = actions.reach_point({1e300, 0, 1}, control::ArmSide::kRight);
  EXPECT_FALSE(huge.sent);
  EXPECT_NE(huge.message.find("within a kilometre"), std::string::npos) << huge.message;
  EXPECT_EQ(arm().point_W_m[0], 0.5);  // Nothing was sent.
  EXPECT_TRUE(actions.grasp(control::ArmSide::kLeft).sent);
  EXPECT_EQ(arm().action, control::ArmAction::kGrasp);
  EXPECT_TRUE(actions.release(control::ArmSide::kNearest).sent);
  EXPECT_EQ(arm().action, control::ArmAction::kRelease);
  EXPECT_EQ(actions.arm_commands_sent(), 4U);
  EXPECT_EQ(actions.gaze_commands_sent(), 0U);
}

TEST_F(RobotActionsTest, AJointMoveGoesToTheLoopThatOwnsItClampedToItsLimits) {
  RobotActions actions(hardware_, setup_, {&gaze_, &arms_, &features_});
  const auto head = actions.move_joint("neck_tilt", 10 * kDeg);
  EXPECT_TRUE(head.sent);
  EXPECT_TRUE(head.message.empty()) << head.message;
  EXPECT_EQ(gaze().action, control::GazeAction::kMoveJoint);
  EXPECT_EQ(gaze().joint_rig_index, rig_index("neck_tilt"));

  const hal::JointLimits& elbow = hardware_.find_joint("right_elbow")->limits;
  const auto clamped = actions.move_joint("right_elbow", -40 * kDeg);
  EXPECT_TRUE(clamped.sent);
  EXPECT_EQ(clamped.message,
            "right_elbow: -40.0 deg is beyond its lower limit; clamped to 0.0 deg");
  EXPECT_EQ(arm().action, control::ArmAction::kMoveJoint);
  EXPECT_EQ(arm().joint_rig_index, rig_index("right_elbow"));
  EXPECT_EQ(arm().position_rad, elbow.min_position_rad);

  const auto unknown = actions.move_joint("right_elbw", 0.1);
  EXPECT_FALSE(unknown.sent);
  EXPECT_EQ(unknown.message, "no joint \"right_elbw\"; did you mean \"right_elbow\"?");
}

TEST_F(RobotActionsTest, WhatCannotBeCarriedOutIsRefusedAndNothingIsSent) {
  RobotActions actions(hardware_, setup_, {&gaze_, nullptr, nullptr});
  EXPECT_EQ(actions.look_at_pixel(-1, 10).message,
            "pixel (-1, 10) is outside the dominant eye's 640x480 image (u in [0, 639], v in [0, "
            "479])");
  // The experiment loader's bounds: the image's last pixel is 639, not 640.
  EXPECT_FALSE(actions.saccade_to_pixel(640, 480).sent);
  EXPECT_FALSE(actions.saccade_to_point({NAN, 0, 1}).sent);
  // Finite but meaningless: refused here, not dropped later by the gaze loop.
  EXPECT_EQ(actions.saccade_to_point({1e300, 1e300, 1e300}).message,
            "the point (1e+300, 1e+300, 1e+300) m is not one the eyes can fixate: every "
            "coordinate within a kilometre of the robot");
  EXPECT_FALSE(actions.look_at_point({0, 0, -1001}).sent);
  EXPECT_FALSE(actions.saccade_by_angles(95 * kDeg, 0).sent);
  EXPECT_FALSE(actions.saccade_by_angles(0, -90 * kDeg).sent);
  EXPECT_EQ(actions.reach_fixated(control::ArmSide::kNearest).message,
            "this run has no arm controller");
  EXPECT_EQ(actions.move_joint("left_wrist", 0.1).message, "this run has no arm controller");
  EXPECT_FALSE(actions.request_features({}).sent);
  EXPECT_EQ(actions.gaze_commands_sent(), 0U);
  EXPECT_EQ(gaze_.version(), 0U);
  EXPECT_TRUE(actions.saccade_to_pixel(639, 479).sent);  // The image's last pixel is on it.
}

TEST_F(RobotActionsTest, FeatureRequestsGoToTheirChannel) {
  RobotActions actions(hardware_, setup_, {&gaze_, &arms_, &features_});
  perception::FeatureRequest request{
      .maps = 3, .disparity = false, .motion = true, .moments = false};
  EXPECT_TRUE(actions.request_features(request).sent);
  perception::FeatureRequest sent;
  ASSERT_TRUE(features_.read(sent));
  EXPECT_EQ(sent.maps, 3U);
  EXPECT_TRUE(sent.motion);
}

}  // namespace
}  // namespace cambio::app
