// The arms in an experiment file: `arm:` and the arm entries of `commands:`.
#include <string>

#include "cambio/config/command_target_bounds.hpp"
#include "experiment_sections.hpp"

namespace cambio::config {

ArmTaskConfig read_arm_task(MapReader arm) {
  // Keys left out keep ArmTaskConfig's member initialisers, the one place of the defaults.
  ArmTaskConfig config;
  config.gain_per_s = arm.number_or("gain", config.gain_per_s, Range::positive());
  config.max_speed_m_s = arm.number_or("max_speed_m_s", config.max_speed_m_s, Range::positive());
  config.max_acceleration_m_s2 =
      arm.number_or("max_acceleration_m_s2", config.max_acceleration_m_s2, Range::positive());
  config.probe_depth_m =
      arm.number_or("probe_depth_m", config.probe_depth_m, Range::closed(0.0, 0.2));
  config.approach_m = arm.number_or("approach_m", config.approach_m, Range::closed(0.0, 0.3));
  config.arrive_tolerance_m =
      arm.number_or("arrive_tolerance_m", config.arrive_tolerance_m, Range::positive());
  config.posture_gain_per_s =
      arm.number_or("posture_gain", config.posture_gain_per_s, Range::non_negative());
  config.gripper_speed_rad_s =
      arm.number_or("gripper_speed_rad_s", config.gripper_speed_rad_s, Range::positive());
  arm.finish();
  return config;
}

ArmCommandConfig read_arm_command(MapReader& entry, std::string_view key) {
  ArmCommandConfig command;
  if (key == "reach") {
    command.action = ArmActionConfig::kReach;
    if (entry.is_list("reach")) {
      command.to_fixation = false;
      command.point_W_m =
          entry.vector3("reach", Range::closed(-kMaxTargetCoordinate_m, kMaxTargetCoordinate_m)
                                     .because("a point within a kilometre of the robot"));
    } else {
      entry.choice("reach", {"fixation"});
    }
    const std::string side = entry.choice_or("arm", {"nearest", "left", "right"}, "nearest");
    command.arm = side == "left"    ? ArmSideConfig::kLeft
                  : side == "right" ? ArmSideConfig::kRight
                                    : ArmSideConfig::kNearest;
    return command;
  }
  command.action = key == "grasp" ? ArmActionConfig::kGrasp : ArmActionConfig::kRelease;
  const std::string side = entry.choice(key, {"both", "left", "right"});
  command.arm = side == "left"    ? ArmSideConfig::kLeft
                : side == "right" ? ArmSideConfig::kRight
                                  : ArmSideConfig::kNearest;
  return command;
}

}  // namespace cambio::config
