// The head's joints found on the shipped rig by walking up from its stereo cameras, and the
// errors for rigs that lack a piece.
#include "cambio/control/head_joints.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"

namespace cambio::control {
namespace {

hal::HardwareInfo shipped_rig() {
  return config::hardware_description(
      config::load_rig(config::find_shipped_config("rigs/cambio.yaml")));
}

/// The message of the std::invalid_argument find_head_joints throws ("" if none).
std::string head_error(const hal::HardwareInfo& hardware) {
  const Kinematics kinematics(hardware);
  try {
    find_head_joints(kinematics, hardware);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(HeadJoints, FindsTheShippedRigsHead) {
  const hal::HardwareInfo hardware = shipped_rig();
  const Kinematics kinematics(hardware);
  const HeadJoints head = find_head_joints(kinematics, hardware);
  EXPECT_EQ(kinematics.joint_name(head.neck_pan), "neck_pan");
  EXPECT_EQ(kinematics.joint_name(head.neck_tilt), "neck_tilt");
  EXPECT_EQ(kinematics.joint_name(head.eye_tilt), "eye_tilt");
  EXPECT_EQ(kinematics.joint_name(head.pan(hal::Eye::kLeft)), "left_eye_pan");
  EXPECT_EQ(kinematics.joint_name(head.pan(hal::Eye::kRight)), "right_eye_pan");
  EXPECT_EQ(kinematics.frame_name(head.camera(hal::Eye::kLeft)), "left_eye");
  EXPECT_EQ(kinematics.frame_name(head.camera(hal::Eye::kRight)), "right_eye");
}

TEST(HeadJoints, NamesTheMissingStereoPair) {
  hal::HardwareInfo hardware = shipped_rig();
  hardware.stereo.reset();
  EXPECT_NE(head_error(hardware).find("no stereo pair"), std::string::npos) << head_error(hardware);
}

TEST(HeadJoints, NamesTheMissingEyeTiltAndTheChainItWalked) {
  // The eyes pan directly on the neck tilt: the chain is one joint short.
  hal::HardwareInfo hardware = shipped_rig();
  for (hal::JointInfo& joint : hardware.joints) {
    if (joint.parent == "eye_tilt") joint.parent = "neck_tilt";
  }
  const std::string message = head_error(hardware);
  EXPECT_NE(message.find("'left_eye' -> 'left_eye_pan' -> 'neck_tilt' -> 'neck_pan' -> base"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("neck pan"), std::string::npos) << message;
}

TEST(HeadJoints, RefusesEyesWithoutASharedTilt) {
  hal::HardwareInfo hardware = shipped_rig();
  // A second tilt for the right eye, on the neck tilt like the first.
  hal::JointInfo right_tilt = *hardware.find_joint("eye_tilt");
  right_tilt.name = "right_eye_tilt";
  for (auto it = hardware.joints.begin(); it != hardware.joints.end(); ++it) {
    if (it->name == "eye_tilt") {
      hardware.joints.insert(it + 1, right_tilt);
      break;
    }
  }
  for (hal::JointInfo& joint : hardware.joints) {
    if (joint.name == "right_eye_pan") joint.parent = "right_eye_tilt";
  }
  for (hal::JointGroupInfo& group : hardware.groups) {
    if (group.name == "head") group.joints.push_back("right_eye_tilt");
  }
  const std::string message = head_error(hardware);
  EXPECT_NE(message.find("do not share an eye tilt"), std::string::npos) << message;
}

TEST(HeadJoints, NamesAStereoCameraThatIsNotACamera) {
  hal::HardwareInfo hardware = shipped_rig();
  hardware.stereo->right_camera = "right_eyeball";
  const std::string message = head_error(hardware);
  EXPECT_NE(message.find("'right_eyeball'"), std::string::npos) << message;
}

}  // namespace
}  // namespace cambio::control
