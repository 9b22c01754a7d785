// The arm as the reach sees it (ArmChain on the shipped rig) and the reach check, against
// independent truth: the closed-form fingertips against the general Kinematics of the rig tree,
// the inverse kinematics by round trips through the forward kinematics, and the refusals by
// targets whose reason is known by construction.
#include "cambio/control/arm_reach_check.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/control/kinematics.hpp"

namespace cambio::control {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
// The shipped rig's fingertips (touch_sensors.*.fingertip_xy_m), which the chain must carry.
constexpr FingerGeometry kFingers{0.082, 0.008};

hal::HardwareInfo shipped_rig() {
  return config::hardware_description(
      config::load_rig(config::find_shipped_config("rigs/cambio.yaml")));
}

std::array<double, 4> random_joints(const ArmChain& arm, std::mt19937& random) {
  std::array<double, 4> q{};
  for (std::size_t k = 0; k < 4; ++k) {
    std::uniform_real_distribution<double> in(arm.limits[k].min_position_rad,
                                              arm.limits[k].max_position_rad);
    q[k] = in(random);
  }
  return q;
}

TEST(ArmChain, FoundOnTheShippedRigWithItsLengths) {
  const hal::HardwareInfo hardware = shipped_rig();
  const ArmChain right = find_arm_chain(hardware, "right_arm");
  EXPECT_TRUE(right.shoulder_W.isApprox(Eigen::Vector3d(0.0, -0.22, 1.05)));
  EXPECT_DOUBLE_EQ(right.upper_arm_m, 0.30);
  EXPECT_DOUBLE_EQ(right.forearm_m, 0.25);
  EXPECT_DOUBLE_EQ(right.wrist_to_gripper_m, 0.08);
  EXPECT_EQ(right.names[0], "right_shoulder_yaw");
  EXPECT_EQ(right.names[4], "right_gripper");
  // Rig order: head (5), left arm (5), right arm (5).
  EXPECT_EQ(right.rig[0], 10);
  EXPECT_EQ(right.rig[4], 14);
  EXPECT_NEAR(right.limits[2].max_position_rad, 140.0 * kDeg, 1e-12);
  EXPECT_TRUE(right.has_touch_sensor);
  EXPECT_DOUBLE_EQ(right.fingers.tip_x_m, kFingers.tip_x_m);
  EXPECT_DOUBLE_EQ(right.fingers.tip_y_m, kFingers.tip_y_m);
  // Closed fingers reach the pads' front faces; open ones come back by cos and the pad's offset.
  EXPECT_DOUBLE_EQ(right.hand_m(0.0), 0.08 + 0.082);
  EXPECT_NEAR(right.hand_m(20.0 * kDeg),
              0.08 + 0.082 * std::cos(20.0 * kDeg) - 0.008 * std::sin(20.0 * kDeg), 1e-15);
  const ArmChain left = find_arm_chain(hardware, "left_arm");
  EXPECT_TRUE(left.shoulder_W.isApprox(Eigen::Vector3d(0.0, 0.22, 1.05)));
}

TEST(ArmChain, RefusesAGroupOfAnotherShape) {
  const hal::HardwareInfo hardware = shipped_rig();
  try {
    (void)find_arm_chain(hardware, "head");
    FAIL() << "the head is not an arm";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("arm 'head': shoulder pitch 'neck_tilt'"),
              std::string::npos)
        << error.what();
  }
  EXPECT_THROW((void)find_arm_chain(hardware, "tail"), std::invalid_argument);
}

TEST(ArmReachCheck, FingertipsAgreeWithTheGeneralKinematics) {
  const hal::HardwareInfo hardware = shipped_rig();
  Kinematics kinematics(hardware);
  std::mt19937 random(7);
  for (const char* group : {"left_arm", "right_arm"}) {
    const ArmChain arm = find_arm_chain(hardware, group);
    for (int trial = 0; trial < 200; ++trial) {
      const std::array<double, 4> q = random_joints(arm, random);
      const double opening = std::uniform_real_distribution<double>(0.0, 40.0 * kDeg)(random);
      std::vector<double> q_tree(static_cast<std::size_t>(kinematics.joint_count()), 0.0);
      for (std::size_t k = 0; k < 4; ++k) q_tree[static_cast<std::size_t>(arm.joints[k])] = q[k];
      q_tree[static_cast<std::size_t>(arm.joints[4])] = opening;
      ASSERT_EQ(kinematics.update(q_tree), hal::Status::kOk);
      // The fingertips' midpoint: the two fingertips of the tree, averaged.
      const Eigen::Isometry3d X_WG =
          kinematics.X_WF(Kinematics::link_frame(arm.joints[4]));  // One finger, turned +opening.
      const Eigen::Isometry3d X_WW = kinematics.X_WF(Kinematics::link_frame(arm.joints[3]));
      const Eigen::Vector3d tip_a = X_WG * Eigen::Vector3d(kFingers.tip_x_m, kFingers.tip_y_m, 0);
      const Eigen::Vector3d mirrored =
          X_WW * (Eigen::Translation3d(arm.wrist_to_gripper_m, 0, 0) *
                  Eigen::AngleAxisd(-opening, Eigen::Vector3d::UnitZ()) *
                  Eigen::Vector3d(kFingers.tip_x_m, -kFingers.tip_y_m, 0));
      EXPECT_LT((fingertips_W(arm, opening, q) - 0.5 * (tip_a + mirrored)).norm(), 1e-12);
    }
  }
}

TEST(ArmReachCheck, SolvesEveryPoseItsJointsCanReachWithALevelishHand) {
  const hal::HardwareInfo hardware = shipped_rig();
  std::mt19937 random(11);
  const HandPitchRange pitches;
  int tried = 0;
  for (const char* group : {"left_arm", "right_arm"}) {
    const ArmChain arm = find_arm_chain(hardware, group);
    for (int trial = 0; trial < 2000; ++trial) {
      const std::array<double, 4> q = random_joints(arm, random);
      const double pitch = q[1] + q[2] + q[3];
      // Poses the check looks among: a hand pitch within range, on its grid of steps.
      if (std::abs(pitch) > pitches.max_deviation_rad) continue;
      const double opening = 20.0 * kDeg;
      const Eigen::Vector3d target = fingertips_W(arm, opening, q);
      const ReachCheck check = check_reach(arm, opening, target, pitches);
      // The check's grid of pitches may miss a pose next to a limit; all the rest must be found.
      if (!check.reachable) {
        bool near_limit = false;
        for (std::size_t k = 1; k < 4; ++k) {
          near_limit |= q[k] - arm.limits[k].min_position_rad < pitches.max_deviation_rad ||
                        arm.limits[k].max_position_rad - q[k] < pitches.max_deviation_rad;
        }
        EXPECT_TRUE(near_limit) << check.why();
        continue;
      }
      ++tried;
      EXPECT_LT((fingertips_W(arm, opening, check.q_rad) - target).norm(), 1e-9);
      for (std::size_t k = 0; k < 4; ++k) {
        EXPECT_GE(check.q_rad[k], arm.limits[k].min_position_rad);
        EXPECT_LE(check.q_rad[k], arm.limits[k].max_position_rad);
      }
      EXPECT_NEAR(check.q_rad[1] + check.q_rad[2] + check.q_rad[3], check.hand_pitch_rad, 1e-12);
    }
  }
  EXPECT_GT(tried, 300);
}

TEST(ArmReachCheck, RefusesBeyondTheArmsLengthSayingBothDistances) {
  const ArmChain arm = find_arm_chain(shipped_rig(), "right_arm");
  const double reach = arm.reach_m(0.0);
  EXPECT_NEAR(reach, 0.30 + 0.25 + 0.162, 1e-12);
  const ReachCheck check =
      check_reach(arm, 0.0, arm.shoulder_W + Eigen::Vector3d(0.9, 0.0, 0.0), {});
  EXPECT_FALSE(check.reachable);
  EXPECT_EQ(check.why(),
            "out of reach: the target is 0.900 m from right_arm's shoulder, the arm reaches "
            "0.712 m");
  // Just within: reachable (straight out, level).
  EXPECT_TRUE(check_reach(arm, 0.0, arm.shoulder_W + Eigen::Vector3d(reach - 1e-6, 0.0, 0.0), {})
                  .reachable);
}

TEST(ArmReachCheck, RefusesAtTheShoulderByTheJointThatCannotFold) {
  // 3 cm in front of the shoulder: the hand (16 cm) would have to fold back over the upper arm,
  // the shoulder pitch beyond +90 deg. Its angle is given in (-180, 180] deg, as its limits.
  const ArmChain arm = find_arm_chain(shipped_rig(), "left_arm");
  const ReachCheck check =
      check_reach(arm, 0.0, arm.shoulder_W + Eigen::Vector3d(0.03, 0.0, 0.0), {});
  EXPECT_FALSE(check.reachable);
  EXPECT_NE(check.why().find("beyond a joint limit: left_shoulder_pitch would need 124."),
            std::string::npos)
      << check.why();
}

TEST(ArmReachCheck, NamesTheJointBeyondItsLimit) {
  const ArmChain left = find_arm_chain(shipped_rig(), "left_arm");
  // Across to the right: the left shoulder's yaw would need -80 deg, its limit is -60.
  const Eigen::Vector3d across =
      left.shoulder_W + 0.5 * Eigen::Vector3d(std::cos(-80.0 * kDeg), std::sin(-80.0 * kDeg), 0);
  const ReachCheck yaw = check_reach(left, 0.0, across, {});
  EXPECT_FALSE(yaw.reachable);
  EXPECT_EQ(yaw.why(),
            "beyond a joint limit: left_shoulder_yaw would need -80.0 deg, its limits are "
            "[-60.0, 90.0] deg");
  // Straight up from the shoulder, close: the shoulder pitch would have to pass -90 deg.
  const ReachCheck up =
      check_reach(left, 0.0, left.shoulder_W + Eigen::Vector3d(0.05, 0.0, 0.6), {});
  EXPECT_FALSE(up.reachable);
  EXPECT_NE(up.why().find("beyond a joint limit: left_shoulder_pitch would need"),
            std::string::npos)
      << up.why();
}

}  // namespace
}  // namespace cambio::control
