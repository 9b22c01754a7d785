#pragma once

#include <array>

#include "cambio/control/kinematics.hpp"
#include "cambio/hal/eye.hpp"
#include "cambio/hal/hardware_info.hpp"

namespace cambio::control {

/// The joints and camera frames of a stereo head with a shared eye tilt (the paper's head: neck
/// pan, neck tilt, eye tilt, one pan per eye), as indices into a Kinematics: joints in tree
/// order (HardwareInfo order), camera frames as Kinematics frames.
struct HeadJoints {
  int neck_pan = -1;
  int neck_tilt = -1;
  int eye_tilt = -1;
  std::array<int, 2> eye_pan{-1, -1};       ///< By hal::Eye (kLeft = 0, kRight = 1).
  std::array<int, 2> camera_frame{-1, -1};  ///< By hal::Eye: the stereo pair's optical frames.

  int pan(hal::Eye eye) const { return eye_pan[static_cast<int>(eye)]; }
  int camera(hal::Eye eye) const { return camera_frame[static_cast<int>(eye)]; }
};

/// Finds the head from the stereo pair's cameras up their parent chains: camera -> eye pan ->
/// eye tilt -> neck tilt -> neck pan, whatever the joints are called. Both chains must meet at
/// the eye tilt. Axes are not checked (the rig file states them; see the plan's conventions).
/// Configure time: throws std::invalid_argument naming what is missing (no stereo pair, an
/// unknown camera, a chain too short to hold the four joints, eyes without a shared tilt), or
/// if `kinematics` was not built from `hardware`.
HeadJoints find_head_joints(const Kinematics& kinematics, const hal::HardwareInfo& hardware);

}  // namespace cambio::control
