// The HAL's hardware description built from a rig: every backend and the kinematics read the
// robot from it, so it must say exactly what the rig file says.
#include "cambio/config/hardware_description.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "cambio/config/rig_loader.hpp"
#include "rig_test_support.hpp"

namespace cambio::config {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(HardwareDescription, CarriesTheShippedRigsJointsGroupsCamerasAndDrives) {
  const RigConfig rig = load_rig(test::shipped_rig_path("cambio.yaml"));
  const hal::HardwareInfo hardware = hardware_description(rig);
  EXPECT_EQ(hardware.name, "cambio");
  ASSERT_EQ(hardware.joints.size(), 15u);
  // Parents before children, whatever the file's order.
  for (std::size_t i = 0; i < hardware.joints.size(); ++i) {
    const std::string& parent = hardware.joints[i].parent;
    if (parent == "base") continue;
    bool seen = false;
    for (std::size_t k = 0; k < i; ++k) seen = seen || hardware.joints[k].name == parent;
    EXPECT_TRUE(seen) << hardware.joints[i].name << " comes before its parent " << parent;
  }
  const hal::JointInfo* eye = hardware.find_joint("left_eye_pan");
  ASSERT_NE(eye, nullptr);
  EXPECT_EQ(eye->parent, "eye_tilt");
  EXPECT_TRUE(eye->X_PJ.translation().isApprox(Eigen::Vector3d(0.0, 0.06, 0.0)));
  EXPECT_TRUE(eye->axis_J.isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_DOUBLE_EQ(eye->limits.max_position_rad, kPi / 4);

  const hal::JointGroupInfo* head = hardware.find_group("head");
  ASSERT_NE(head, nullptr);
  EXPECT_EQ(head->backend, "sim");
  EXPECT_EQ(head->rate_hz, 400.0);  // loops.joint.rate_hz: the head sets none of its own.
  EXPECT_EQ(hardware.find_group("left_arm")->rate_hz, 250.0);
  ASSERT_EQ(head->limits.size(), 5u);
  EXPECT_DOUBLE_EQ(head->limits[0].min_position_rad, -kPi / 2);

  ASSERT_TRUE(hardware.stereo.has_value());
  EXPECT_EQ(hardware.stereo->baseline_m, 0.12);
  const hal::CameraInfo* camera = hardware.find_camera("right_eye");
  ASSERT_NE(camera, nullptr);
  EXPECT_EQ(camera->parent_frame, "right_eye_pan");
  EXPECT_EQ(camera->intrinsics.width_px, 640);
  EXPECT_EQ(camera->rate_hz, 30.0);
  EXPECT_TRUE(camera->distortion.is_zero());
  // rpy (-90, 0, -90) deg turns the optical axis (z) onto the link's forward x, image x (right)
  // onto the link's -y and image y (down) onto -z.
  const Eigen::Matrix3d R = camera->X_PC.linear();
  EXPECT_TRUE((R * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_TRUE((R * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_TRUE((R * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitZ(), 1e-12));
  EXPECT_TRUE(camera->X_PC.translation().isApprox(Eigen::Vector3d(0.02, 0.0, 0.0)));
  EXPECT_EQ(hardware.touch_sensors.size(), 2u);
}

TEST(HardwareDescription, PoseFollowsUrdfsRollPitchYawOrder) {
  Pose pose;
  pose.rpy_rad = {0.1, 0.2, 0.3};
  pose.xyz_m = {1.0, 2.0, 3.0};
  const Eigen::Isometry3d X = to_isometry(pose);
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  EXPECT_TRUE(X.linear().isApprox(expected, 1e-15));
  EXPECT_EQ(X.translation(), Eigen::Vector3d(1.0, 2.0, 3.0));
}

TEST(JointLoopSettings, WatchdogTimeoutsLoadWithDefaultsAndRanges) {
  const RigConfig shipped = load_rig(test::shipped_rig_path("pan_tilt.yaml"));
  EXPECT_EQ(shipped.find_loop("joint")->command_timeout_s, 0.1);
  EXPECT_EQ(shipped.find_loop("joint")->feedback_timeout_s, 0.02);

  const RigConfig set = load_rig(test::shipped_rig_path("cambio.yaml"),
                                 {parse_override("loops.joint.command_timeout_s=0.25"),
                                  parse_override("loops.joint.feedback_timeout_s=0.004")});
  EXPECT_EQ(set.find_loop("joint")->command_timeout_s, 0.25);
  EXPECT_EQ(set.find_loop("joint")->feedback_timeout_s, 0.004);

  try {
    (void)load_rig(test::shipped_rig_path("cambio.yaml"),
                   {parse_override("loops.joint.feedback_timeout_s=0"),
                    parse_override("loops.control.command_timeout_s=1")});
    FAIL() << "accepted a zero timeout and a watchdog on the control loop";
  } catch (const ConfigError& error) {
    const std::string text = error.what();
    EXPECT_NE(text.find("loops.joint.feedback_timeout_s"), std::string::npos) << text;
    EXPECT_NE(text.find("loops.control.command_timeout_s"), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace cambio::config
