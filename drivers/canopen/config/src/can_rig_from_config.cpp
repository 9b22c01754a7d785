#include "cambio/canopen/can_rig_from_config.hpp"

namespace cambio::canopen {

CanRigInfo can_rig_from_config(const config::RigConfig& rig) {
  CanRigInfo can_rig;
  for (const auto& bus : rig.can_buses) {
    can_rig.buses.push_back(
        {bus.name, bus.interface, bus.bitrate_bit_s, bus.fd, bus.data_bitrate_bit_s});
  }
  for (const auto& group : rig.groups) {
    CanGroupInfo info;
    info.name = group.name;
    info.bus = group.can_bus;
    info.settings.heartbeat_period_s = group.can.heartbeat_period_s;
    info.settings.stale_after_missed_syncs = group.can.stale_after_missed_syncs;
    info.settings.sdo_timeout_s = group.can.sdo_timeout_s;
    info.settings.velocity_feedforward = group.can.velocity_feedforward;
    info.settings.effort_feedforward = group.can.effort_feedforward;
    info.settings.velocity_feedback = group.can.velocity_feedback;
    info.settings.effort_feedback = group.can.effort_feedback;
    can_rig.groups.push_back(std::move(info));
  }
  for (const auto& joint : rig.joints) {
    if (!joint.can) continue;
    JointDriveInfo drive;
    drive.node_id = joint.can->node_id;
    drive.gear_ratio = joint.can->gear_ratio;
    drive.encoder_counts_per_rev = joint.can->encoder_counts_per_rev;
    drive.following_error_window_rad = joint.can->following_error_window_rad;
    drive.mode = joint.servo.command == config::ServoCommandMode::kVelocity
                     ? hal::CommandMode::kVelocity
                     : hal::CommandMode::kPosition;
    if (const auto& homing = joint.can->homing) {
      drive.homing = HomingSettings{homing->method,           homing->switch_speed_rad_s,
                                    homing->zero_speed_rad_s, homing->acceleration_rad_s2,
                                    homing->offset_rad,       homing->timeout_s};
    }
    can_rig.drives[joint.name] = drive;
  }
  return can_rig;
}

}  // namespace cambio::canopen
