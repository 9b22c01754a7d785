#pragma once

#include <array>
#include <cstdint>

#include "cambio/hal/joint_group.hpp"

namespace cambio::control {

/// Upper bound on the joints one runtime drives (the Câmbio rig has 15). Fixed so that joint
/// frames are trivially copyable and move through SeqlockChannel without allocation.
inline constexpr int kMaxJoints = 32;

/// Targets for every joint of the rig, in rig order, from the control loop to the joint loop.
struct JointTargetFrame {
  std::int64_t stamp_ns = 0;  ///< When the control loop produced them; the watchdog reads it.
  int count = 0;
  std::array<hal::JointCommand, kMaxJoints> commands{};
};

/// What the encoders said, for every joint in rig order, from the joint loop to everyone else.
struct JointStateFrame {
  std::int64_t stamp_ns = 0;
  int count = 0;
  std::array<hal::JointState, kMaxJoints> states{};
};

}  // namespace cambio::control
