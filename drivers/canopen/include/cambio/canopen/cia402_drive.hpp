#pragma once

// The master's side of one CiA 402 drive: what the drive last reported, what the layers above
// asked, and the controlword and target to send next. Walks controlwords one transition at a time
// (cia402::controlword_toward); a drive is driven only once it has been seen operation enabled
// for a cycle: until then, and on the first cycle after, the target is the measured position
// (enabling never jumps to an old target, cf. ros2_control's command jump on re-activation).
// Header-only, no allocation; the joint loop's thread owns it.

#include <cstdint>

#include "cambio/canopen/cia402.hpp"
#include "cambio/canopen/pdo_codec.hpp"
#include "cambio/canopen/torque_units.hpp"
#include "cambio/hal/drive_state.hpp"
#include "cambio/hal/joint_group.hpp"

namespace cambio::canopen {

class Cia402Drive {
 public:
  Cia402Drive() = default;
  Cia402Drive(int node_id, cia402::Units units, hal::CommandMode mode)
      : node_id_(node_id), units_(units), mode_(mode) {}

  int node_id() const { return node_id_; }
  const cia402::Units& units() const { return units_; }
  hal::CommandMode mode() const { return mode_; }
  /// The drive's rated torque (read at configure) for the torque offset and torque actual value.
  void set_torque_units(TorqueUnits torque) { torque_ = torque; }
  const TorqueUnits& torque_units() const { return torque_; }

  /// A statusword and position (and optional velocity/torque) the drive reported.
  void on_feedback(const DriveFeedback& feedback) {
    feedback_ = feedback;
    state_ = cia402::drive_state_of(feedback.statusword);
    if (!hal::is_enabled(state_)) enabled_cycles_ = 0;
  }
  const DriveFeedback& feedback() const { return feedback_; }
  hal::DriveState state() const { return state_; }
  double position_rad() const { return units_.to_rad(feedback_.position_counts); }

  void request(hal::DriveRequest request) { request_ = request; }
  hal::DriveRequest requested() const { return request_; }

  /// This cycle's controlword and targets. `command` is already clamped; `hold` (a fault or loss
  /// in the group) turns an enable into a quick stop and the target into the measured position;
  /// `unhomed` (a joint that must home and has not) turns it into disable: never driven.
  DriveTargets next_targets(const hal::JointCommand& command, bool hold, bool unhomed = false) {
    hal::DriveRequest effective = request_;
    if (hold && effective == hal::DriveRequest::kEnable) effective = hal::DriveRequest::kQuickStop;
    if (unhomed && effective != hal::DriveRequest::kFaultReset) {
      effective = hal::DriveRequest::kDisable;
    }
    controlword_ = cia402::controlword_toward(state_, effective, controlword_);

    // Driven only after a whole cycle seen enabled, and never while holding.
    const bool driven = !hold && hal::is_enabled(state_) && enabled_cycles_ > 0 &&
                        effective == hal::DriveRequest::kEnable;
    if (hal::is_enabled(state_)) ++enabled_cycles_;

    DriveTargets targets;
    targets.controlword = controlword_;
    targets.target_position_counts = feedback_.position_counts;
    targets.target_velocity_counts_s = 0;
    if (driven) {
      if (mode_ == hal::CommandMode::kPosition && command.mode == hal::CommandMode::kPosition) {
        targets.target_position_counts = units_.to_counts(command.value);
        targets.velocity_offset_counts_s = units_.to_counts(command.velocity_feedforward_rad_s);
      } else if (mode_ == hal::CommandMode::kVelocity &&
                 command.mode == hal::CommandMode::kVelocity) {
        targets.target_velocity_counts_s = units_.to_counts(command.value);
      }
      if (command.mode == mode_) {
        targets.torque_offset_per_mille = torque_.to_per_mille(command.effort_feedforward_nm);
      }
      // A command in the other mode than the drive's is not executed: the drive holds.
    }
    return targets;
  }
  std::uint16_t last_controlword() const { return controlword_; }

 private:
  int node_id_ = 0;
  cia402::Units units_{};
  TorqueUnits torque_{};
  hal::CommandMode mode_ = hal::CommandMode::kPosition;
  DriveFeedback feedback_{};
  hal::DriveState state_ = hal::DriveState::kNotReadyToSwitchOn;
  hal::DriveRequest request_ = hal::DriveRequest::kDisable;
  std::uint16_t controlword_ = cia402::kControlDisableVoltage;
  std::uint32_t enabled_cycles_ = 0;
};

}  // namespace cambio::canopen
