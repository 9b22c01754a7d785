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
/// Each state carries its own stamp, drive state and status bits (including the loop's latched
/// and stale bits).
struct JointStateFrame {
  std::int64_t stamp_ns = 0;  ///< The newest of the joints' stamps.
  int count = 0;
  std::array<hal::JointState, kMaxJoints> states{};
  /// The loop sends no motion: a latched fault or lost joint (until a fault reset), or stale
  /// feedback (until fresh readings arrive).
  bool holding = false;
  bool fault_latched = false;
};

}  // namespace cambio::control
