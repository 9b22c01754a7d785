#include "cambio/canopen/eds/eds_group_needs.hpp"

#include <stdexcept>

#include "cambio/canopen/cia402.hpp"
#include "cambio/canopen/drive_parameters.hpp"
#include "cambio/canopen/node_reconfiguration.hpp"
#include "cambio/canopen/pdo_configuration.hpp"

namespace cambio::canopen::eds {

CanGroupView can_group_view(const hal::HardwareInfo& hardware, const CanRigInfo& can_rig,
                            std::string_view group_name, double default_rate_hz) {
  const hal::JointGroupInfo* group = hardware.find_group(group_name);
  const CanGroupInfo* can_group = can_rig.find_group(group_name);
  if (group == nullptr || can_group == nullptr) {
    std::string names;
    for (const auto& known : hardware.groups) names += (names.empty() ? "" : ", ") + known.name;
    throw std::invalid_argument("no group '" + std::string(group_name) + "' in the rig (it has " +
                                names + ")");
  }
  if (can_group->bus.empty()) {
    throw std::invalid_argument("group '" + group->name + "' names no CAN bus (groups." +
                                group->name + ".can_bus)");
  }
  CanGroupView view;
  view.group = *group;
  if (!(view.group.rate_hz > 0.0)) view.group.rate_hz = default_rate_hz;
  view.settings = can_group->settings;
  for (const std::string& joint_name : group->joints) {
    const hal::JointInfo* joint = hardware.find_joint(joint_name);
    const JointDriveInfo* drive = can_rig.find_drive(joint_name);
    if (joint == nullptr || drive == nullptr) {
      throw std::invalid_argument("joint '" + joint_name + "' of group '" + group->name +
                                  "' has no CAN drive (joints." + joint_name + ".can)");
    }
    view.joints.push_back(*joint);
    view.drives.push_back(*drive);
  }
  return view;
}

PdoLayout master_pdo_layout(const CanGroupView& view) {
  // The group's first drive decides the mode, as CanJointGroup does; can_rig_check refuses
  // groups whose drives disagree.
  const hal::CommandMode mode =
      view.drives.empty() ? hal::CommandMode::kPosition : view.drives.front().mode;
  return pdo_layout(mode, view.settings);
}

std::vector<ObjectUse> master_object_uses(const CanGroupView& view, std::size_t joint) {
  const JointDriveInfo& drive = view.drives.at(joint);
  std::vector<ObjectUse> uses;
  // configure_group() reads the device type before anything else.
  uses.push_back({ObjectUse::Kind::kRead, {{kDeviceType, 0}, 0, 4}});
  std::vector<ObjectWrite> writes = drive_parameter_writes(view.joints.at(joint), drive, view.group,
                                                           view.settings, view.group.rate_hz);
  const std::vector<ObjectWrite> homing = homing_parameter_writes(view.joints.at(joint), drive);
  writes.insert(writes.end(), homing.begin(), homing.end());
  // The PDOs the layout leaves empty the master only disables where the drive has them
  // (pdo_configuration.hpp): they are no need.
  const PdoLayout layout = master_pdo_layout(view);
  PdoPresence mapped;
  for (std::size_t k = 0; k < mapped.rpdos.size(); ++k) {
    mapped.rpdos[k] = k < layout.rpdos.size() && !layout.rpdos[k].empty();
    mapped.tpdos[k] = k < layout.tpdos.size() && !layout.tpdos[k].empty();
  }
  const std::vector<ObjectWrite> pdos = pdo_configuration_writes(drive.node_id, layout, mapped);
  writes.insert(writes.end(), pdos.begin(), pdos.end());
  for (const ReconfigurationStep& step : reconfiguration_plan(writes)) {
    switch (step.kind) {
      case ReconfigurationStep::Kind::kWrite:
        uses.push_back({ObjectUse::Kind::kWrite, step.write});
        break;
      case ReconfigurationStep::Kind::kVerify:
      case ReconfigurationStep::Kind::kReadStatusword:
      case ReconfigurationStep::Kind::kReadPosition:
        uses.push_back({ObjectUse::Kind::kRead, step.write});
        break;
      case ReconfigurationStep::Kind::kNmtStart:
        break;
    }
  }
  if (view.settings.effort_feedforward || view.settings.effort_feedback) {
    uses.push_back({ObjectUse::Kind::kRead, {cia402::kRatedTorque, 0, 4}});
  }
  return uses;
}

ObjectPurpose object_purpose(ObjectAddress object, const CanGroupView& view, std::size_t joint) {
  const std::string joint_key = "joints." + view.joints.at(joint).name;
  const std::string group_key = "groups." + view.group.name;
  const std::uint16_t index = object.index;
  if (index == kDeviceType) return {"device type: the master checks the drive is CiA 402", ""};
  if (index == kProducerHeartbeatTime) {
    return {"producer heartbeat time: the master declares a drive lost after 3 missed heartbeats",
            group_key + ".can.heartbeat_period_ms"};
  }
  if (index >= kRpdoCommunication && index < kTpdoMapping + 0x200) {
    return {
        "PDO configuration: the master sets up the PDOs it maps (RPDO1-2, TPDO1-2) and "
        "disables the others the drive has",
        group_key + ".can.feedforward / .can.feedback"};
  }
  if (object == cia402::kModesOfOperation) {
    return {"modes of operation: CSP (8) or CSV (9)", joint_key + ".servo.command"};
  }
  if (index == cia402::kMinSoftwarePositionLimit.index) {
    return {"software position limits, counts", joint_key + ".min_position_* / .max_position_*"};
  }
  if (object == cia402::kMaxProfileVelocity) {
    return {"max profile velocity, counts/s", joint_key + ".max_velocity_rad_s"};
  }
  if (object == cia402::kFollowingErrorWindow) {
    return {"following error window, counts",
            joint_key + ".can.following_error_window_* (0: not written)", true};
  }
  if (index == cia402::kInterpolationTimePeriod.index) {
    return {"interpolation time period: the SYNC period", group_key + ".rate_hz"};
  }
  if (object == cia402::kRatedTorque) {
    return {"rated torque: converts effort offsets and readings",
            group_key + ".can.feedforward / .can.feedback (effort)", true};
  }
  if (object == cia402::kVelocityOffset || object == cia402::kTorqueOffset) {
    return {"feed-forward in RPDO2", group_key + ".can.feedforward", true};
  }
  if (object == cia402::kVelocityActualValue || object == cia402::kTorqueActualValue) {
    return {"feedback in TPDO2", group_key + ".can.feedback", true};
  }
  if (object == cia402::kHomingMethod || index == cia402::kHomingSwitchSpeed.index ||
      object == cia402::kHomingAcceleration || object == cia402::kHomeOffset) {
    return {"homing (CiA 402 mode 6) at the start of a run", joint_key + ".can.homing", true};
  }
  if (object == cia402::kTargetPosition || object == cia402::kTargetVelocity) {
    return {"the cyclic target in RPDO1", joint_key + ".servo.command"};
  }
  return {"needed by the master on every drive (controlword, statusword, position)", ""};
}

}  // namespace cambio::canopen::eds
