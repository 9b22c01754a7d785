#include "cambio/control/head_joints.hpp"

#include <stdexcept>
#include <string>

namespace cambio::control {

namespace {

/// The joint a link hangs from, as hardware names it; "" for a link on the base.
std::string parent_joint(const hal::HardwareInfo& hardware, const std::string& joint_name) {
  const hal::JointInfo* joint = hardware.find_joint(joint_name);
  if (joint == nullptr || joint->parent == Kinematics::kBase) return {};
  return joint->parent;
}

}  // namespace

HeadJoints find_head_joints(const Kinematics& kinematics, const hal::HardwareInfo& hardware) {
  const std::string where = "head of '" + hardware.name + "': ";
  if (!hardware.stereo) {
    throw std::invalid_argument(where + "the rig has no stereo pair (rig file key 'stereo')");
  }
  auto index = [&](const std::string& joint) {
    const int found = kinematics.find_joint(joint);
    if (found < 0) {
      throw std::invalid_argument(where + "joint '" + joint +
                                  "' is not in the kinematics (built from another rig?)");
    }
    return found;
  };

  HeadJoints head;
  std::array<std::string, 2> eye_tilts;
  for (const hal::Eye eye : {hal::Eye::kLeft, hal::Eye::kRight}) {
    const std::string& camera_name =
        eye == hal::Eye::kLeft ? hardware.stereo->left_camera : hardware.stereo->right_camera;
    const hal::CameraInfo* camera = hardware.find_camera(camera_name);
    if (camera == nullptr) {
      throw std::invalid_argument(where + "the stereo pair's " + std::string(to_string(eye)) +
                                  " camera '" + camera_name + "' is not among the cameras");
    }
    const int frame = kinematics.find_frame(camera_name);
    if (frame < 0) {
      throw std::invalid_argument(where + "camera '" + camera_name +
                                  "' is not in the kinematics (built from another rig?)");
    }
    // camera -> eye pan -> eye tilt -> neck tilt -> neck pan.
    std::array<std::string, 4> chain;
    chain[0] = camera->parent_frame == Kinematics::kBase ? "" : camera->parent_frame;
    for (std::size_t i = 1; i < chain.size() && !chain[i - 1].empty(); ++i) {
      chain[i] = parent_joint(hardware, chain[i - 1]);
    }
    static constexpr std::array<const char*, 4> kRoles = {"eye pan", "eye tilt", "neck tilt",
                                                          "neck pan"};
    for (std::size_t i = 0; i < chain.size(); ++i) {
      if (!chain[i].empty()) continue;
      std::string path = "'" + camera_name + "'";
      for (std::size_t k = 0; k < i; ++k) path += " -> '" + chain[k] + "'";
      throw std::invalid_argument(
          where + "the " + std::string(to_string(eye)) + " camera's chain " + path +
          " -> base has no joint for the " + kRoles[i] +
          " (a head is camera -> eye pan -> eye tilt -> neck tilt -> neck pan)");
    }
    const int e = static_cast<int>(eye);
    head.camera_frame[e] = frame;
    head.eye_pan[e] = index(chain[0]);
    eye_tilts[e] = chain[1];
    if (eye == hal::Eye::kLeft) {
      head.eye_tilt = index(chain[1]);
      head.neck_tilt = index(chain[2]);
      head.neck_pan = index(chain[3]);
    }
  }
  if (eye_tilts[0] != eye_tilts[1]) {
    throw std::invalid_argument(where +
                                "the eyes do not share an eye tilt: the left eye pans on '" +
                                eye_tilts[0] + "', the right on '" + eye_tilts[1] + "'");
  }
  if (head.eye_pan[0] == head.eye_pan[1]) {
    throw std::invalid_argument(where + "both cameras sit on the same eye pan joint '" +
                                kinematics.joint_name(head.eye_pan[0]) + "'");
  }
  return head;
}

}  // namespace cambio::control
