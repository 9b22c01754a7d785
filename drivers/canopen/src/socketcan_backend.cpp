#include "cambio/canopen/socketcan_backend.hpp"

#include <cmath>
#include <set>
#include <stdexcept>

#include "cambio/canopen/drive_parameters.hpp"
#include "cambio/canopen/homing.hpp"
#include "cambio/canopen/nmt_master.hpp"
#include "cambio/canopen/object_write.hpp"
#include "cambio/canopen/pdo_configuration.hpp"
#include "cambio/canopen/sdo_transfer.hpp"

namespace cambio::canopen {

namespace {

std::string in_quotes(std::string_view name) {
  return "'" + std::string(name) + "'";
}

std::int64_t to_ns(double seconds) {
  return static_cast<std::int64_t>(std::llround(seconds * 1e9));
}

/// Forwards to a group the backend owns, so deactivate() can reach the drives whatever the
/// application did with the handle.
class CanJointGroupHandle final : public hal::JointGroup {
 public:
  explicit CanJointGroupHandle(CanJointGroup& group) : group_(group) {}
  const hal::JointGroupInfo& info() const override { return group_.info(); }
  hal::Status read(std::span<hal::JointState> out, std::int64_t& stamp_ns) override {
    return group_.read(out, stamp_ns);
  }
  hal::Status write(std::span<const hal::JointCommand> commands) override {
    return group_.write(commands);
  }
  hal::Status request(hal::DriveRequest request, int joint) override {
    return group_.request(request, joint);
  }
  hal::Status sync() override { return group_.sync(); }

 private:
  CanJointGroup& group_;
};

/// The homing parameters; a drive that refuses the method (an SDO abort on 0x6098, as a drive
/// without that method answers) is reported as such.
void write_homing_parameters(BusPump& pump, int node, const JointDriveInfo& drive,
                             std::span<const ObjectWrite> writes, double sdo_timeout_s) {
  for (const ObjectWrite& write : writes) {
    try {
      sdo_write_value(pump, node, write.object, write.value, write.bytes, sdo_timeout_s);
    } catch (const SdoError& error) {
      if (write.object != cia402::kHomingMethod) throw;
      throw SdoError("homing method " + std::to_string(drive.homing->method) +
                         " refused by the drive: " + error.what(),
                     error.abort_code());
    }
  }
}

/// Which PDOs the drive has, asked only for those the layout leaves empty (a mapped one must
/// exist: its configuration fails naming it otherwise).
PdoPresence pdo_presence(BusPump& pump, int node, const PdoLayout& layout, double sdo_timeout_s) {
  PdoPresence present;
  const auto has = [&](std::uint16_t communication) {
    try {
      (void)sdo_read_value(pump, node, ObjectAddress{communication, 1}, sdo_timeout_s);
      return true;
    } catch (const SdoError& error) {
      if (error.abort_code() != static_cast<std::uint32_t>(SdoAbortCode::kObjectDoesNotExist)) {
        throw;
      }
      return false;
    }
  };
  for (std::size_t k = 0; k < 4; ++k) {
    const auto offset = static_cast<std::uint16_t>(k);
    if (k >= layout.rpdos.size() || layout.rpdos[k].empty()) {
      present.rpdos[k] = has(static_cast<std::uint16_t>(kRpdoCommunication + offset));
    }
    if (k >= layout.tpdos.size() || layout.tpdos[k].empty()) {
      present.tpdos[k] = has(static_cast<std::uint16_t>(kTpdoCommunication + offset));
    }
  }
  return present;
}

}  // namespace

SocketCanBackend::SocketCanBackend(const hal::HardwareInfo& hardware, CanRigInfo can_rig,
                                   const hal::BackendContext& context, BusOpener opener,
                                   SocketCanBackendOptions options)
    : hardware_(hardware),
      can_rig_(std::move(can_rig)),
      clock_(*context.clock),
      opener_(std::move(opener)),
      options_(std::move(options)) {
  if (!opener_) throw std::invalid_argument("socketcan: no bus opener given");
}

SocketCanBackend::~SocketCanBackend() {
  deactivate();
}

std::unique_ptr<hal::JointGroup> SocketCanBackend::make_joint_group(std::string_view group_name) {
  const hal::JointGroupInfo* info = hardware_.find_group(group_name);
  if (info == nullptr) {
    throw std::runtime_error("socketcan: the rig has no joint group " + in_quotes(group_name));
  }
  if (info->backend != kName) {
    throw hal::BackendUnavailable("socketcan: joint group " + in_quotes(group_name) +
                                  " names backend " + in_quotes(info->backend) +
                                  ", not 'socketcan'");
  }
  if (groups_.count(group_name) != 0) {
    throw std::runtime_error("socketcan: joint group " + in_quotes(group_name) +
                             " was already made (one writer per group)");
  }
  const CanGroupInfo* can_group = can_rig_.find_group(group_name);
  const CanBusInfo* bus_info = can_group != nullptr ? can_rig_.find_bus(can_group->bus) : nullptr;
  if (bus_info == nullptr) {
    throw std::runtime_error("socketcan: joint group " + in_quotes(group_name) + " names CAN bus " +
                             in_quotes(can_group != nullptr ? can_group->bus : "") +
                             ", which the rig's can_buses do not list");
  }
  const auto used = buses_.find(bus_info->name);
  if (used != buses_.end()) {
    throw std::runtime_error("socketcan: joint groups " + in_quotes(used->second.group) + " and " +
                             in_quotes(group_name) + " share CAN bus " + in_quotes(bus_info->name) +
                             "; each CAN group produces its bus's SYNC at its own rate, so one "
                             "group per bus");
  }
  std::vector<JointDriveInfo> drives;
  for (const std::string& joint_name : info->joints) {
    const JointDriveInfo* drive = can_rig_.find_drive(joint_name);
    if (drive == nullptr) {
      throw std::runtime_error("socketcan: joint " + in_quotes(joint_name) + " of group " +
                               in_quotes(group_name) + " has no CAN drive (can.node_id)");
    }
    drives.push_back(*drive);
  }
  const double rate_hz = info->rate_hz > 0.0 ? info->rate_hz : options_.default_joint_rate_hz;

  Bus bus{*bus_info, opener_(*bus_info), std::string(group_name)};
  if (bus.bus == nullptr) {
    throw std::runtime_error("socketcan: could not open CAN bus " + in_quotes(bus_info->name) +
                             " (interface " + in_quotes(bus_info->interface) + ")");
  }
  auto group = std::make_unique<CanJointGroup>(*info, can_group->settings, std::move(drives),
                                               rate_hz, *bus.bus, clock_);
  group->set_bus_bitrate(bus_info->bitrate_bit_s);
  auto handle = std::make_unique<CanJointGroupHandle>(*group);
  buses_.emplace(bus_info->name, std::move(bus));
  groups_.emplace(std::string(group_name), std::move(group));
  return handle;
}

std::unique_ptr<hal::Camera> SocketCanBackend::make_camera(std::string_view camera_name) {
  throw hal::BackendUnavailable("socketcan: camera " + in_quotes(camera_name) +
                                ": the socketcan backend drives joints only");
}

std::unique_ptr<hal::TouchSensor> SocketCanBackend::make_touch_sensor(
    std::string_view sensor_name) {
  throw hal::BackendUnavailable("socketcan: touch sensor " + in_quotes(sensor_name) +
                                ": the socketcan backend drives joints only");
}

const CanJointGroup* SocketCanBackend::group(std::string_view group_name) const {
  const auto it = groups_.find(group_name);
  return it == groups_.end() ? nullptr : it->second.get();
}

void SocketCanBackend::configure() {
  for (auto& [name, group] : groups_) configure_group(*group, *hardware_.find_group(name));
  configured_ = true;
}

void SocketCanBackend::configure_group(CanJointGroup& group, const hal::JointGroupInfo& info) {
  const CanGroupSettings& settings = group.settings();
  const double sdo_timeout_s = settings.sdo_timeout_s;
  const std::string where = "socketcan: joint group " + in_quotes(info.name) + " on CAN bus " +
                            in_quotes(can_rig_.find_group(info.name)->bus) + " (" +
                            group.bus().name() + ")";
  BusPump pump(group.bus(), clock_, options_.waiter);
  std::set<int> booted;
  pump.set_other_frame_handler([&booted](const hal::CanFrame& frame) {
    if (function_of(frame.id) == 0x700 && !frame.extended_id) {
      const auto state = heartbeat_state(frame);
      if (state == NmtState::kBootUp) booted.insert(node_of(frame.id));
    }
  });

  // Reset communication: every drive restarts its communication objects (PDO mappings included)
  // and announces itself with a boot-up.
  for (std::size_t k = 0; k < group.size(); ++k) {
    pump.send(nmt_frame(NmtCommand::kResetCommunication, group.drive(k).node_id()),
              to_ns(sdo_timeout_s), where + ": NMT reset communication");
  }
  (void)pump.pump_until([](const hal::CanFrame&) { return false; },
                        [&] { return booted.size() >= group.size(); },
                        to_ns(options_.boot_timeout_s));

  std::vector<std::string> mismatches;
  for (std::size_t k = 0; k < group.size(); ++k) {
    const int node = group.drive(k).node_id();
    const hal::JointInfo& joint = *hardware_.find_joint(info.joints[k]);
    const std::string what = "joint " + in_quotes(joint.name);
    try {
      // A drive that sent no boot-up must at least answer: its device type says it is CiA 402.
      const std::uint32_t device_type =
          sdo_read_value(pump, node, ObjectAddress{kDeviceType, 0}, sdo_timeout_s);
      if ((device_type & 0xFFFF) != (cia402::kDeviceTypeServoDrive & 0xFFFF)) {
        throw std::runtime_error("node " + std::to_string(node) + ": device type " +
                                 describe_value({{kDeviceType, 0}, 0, 4}, device_type) +
                                 " is not a CiA 402 drive");
      }
      const std::vector<ObjectWrite> parameters = drive_parameter_writes(
          joint, *can_rig_.find_drive(joint.name), info, settings, group.rate_hz());
      const JointDriveInfo& drive = *can_rig_.find_drive(joint.name);
      const std::vector<ObjectWrite> homing = homing_parameter_writes(joint, drive);
      const std::vector<ObjectWrite> pdos = pdo_configuration_writes(
          node, group.layout(), pdo_presence(pump, node, group.layout(), sdo_timeout_s));
      write_objects(pump, node, parameters, sdo_timeout_s);
      write_homing_parameters(pump, node, drive, homing, sdo_timeout_s);
      write_objects(pump, node, pdos, sdo_timeout_s);
      for (auto* writes : {&parameters, &homing, &pdos}) {
        auto found = verify_objects(pump, node, what, *writes, sdo_timeout_s);
        mismatches.insert(mismatches.end(), found.begin(), found.end());
      }
      // The replay a reboot needs, precomputed here: the loop side does not allocate.
      std::vector<ObjectWrite> configuration = parameters;
      configuration.insert(configuration.end(), homing.begin(), homing.end());
      configuration.insert(configuration.end(), pdos.begin(), pdos.end());
      group.set_configuration(k, configuration);
      if (settings.effort_feedforward || settings.effort_feedback) {
        // Torque offset and torque actual value count per mille of this (torque_units.hpp).
        const std::uint32_t rated_mnm =
            sdo_read_value(pump, node, cia402::kRatedTorque, sdo_timeout_s);
        if (rated_mnm == 0) {
          throw std::runtime_error("node " + std::to_string(node) +
                                   ": rated torque (0x6076:00) is 0 mN m, so effort feed-forward "
                                   "and feedback cannot be converted; set it in the drive or "
                                   "turn effort_feedforward and effort_feedback off");
        }
        group.set_rated_torque(k, static_cast<double>(rated_mnm) * 1e-3);
      }
      DriveFeedback feedback;
      feedback.statusword = static_cast<std::uint16_t>(
          sdo_read_value(pump, node, cia402::kStatusword, sdo_timeout_s));
      feedback.position_counts =
          sign_extend(sdo_read_value(pump, node, cia402::kPositionActualValue, sdo_timeout_s), 4);
      group.seed_feedback(k, feedback, clock_.now_ns());
    } catch (const std::exception& error) {
      throw std::runtime_error(
          where + ", " + what + ": " + error.what() +
          (booted.count(node) == 0 ? " (no boot-up was seen from node " + std::to_string(node) + ")"
                                   : ""));
    }
  }
  if (!mismatches.empty()) {
    std::string text = where + ": drives did not take their parameters; not enabling:";
    for (const std::string& mismatch : mismatches) text += "\n  " + mismatch;
    throw std::runtime_error(text);
  }
  for (std::size_t k = 0; k < group.size(); ++k) {
    pump.send(nmt_frame(NmtCommand::kStart, group.drive(k).node_id()), to_ns(sdo_timeout_s),
              where + ": NMT start");
  }
}

void SocketCanBackend::activate() {
  if (!configured_) throw std::logic_error("socketcan: activate() before configure()");
  for (auto& [name, group] : groups_) home_group(*group, *hardware_.find_group(name));
  for (auto& [name, group] : groups_) group->arm(clock_.now_ns());
  active_ = true;
}

void SocketCanBackend::home_group(CanJointGroup& group, const hal::JointGroupInfo& info) {
  const double sdo_timeout_s = group.settings().sdo_timeout_s;
  BusPump pump(group.bus(), clock_, options_.waiter);
  for (std::size_t k = 0; k < group.size(); ++k) {
    const JointDriveInfo& drive = *can_rig_.find_drive(info.joints[k]);
    if (!drive.homing) continue;
    try {
      HomingRecord record =
          home_drive(pump, info.joints[k], drive.node_id, *drive.homing, drive.mode, sdo_timeout_s);
      group.seed_feedback(k, record.feedback, clock_.now_ns());
      group.set_homed(k, std::move(record));
    } catch (const std::exception& error) {
      throw std::runtime_error("socketcan: joint group " + in_quotes(info.name) + ": " +
                               error.what());
    }
  }
}

void SocketCanBackend::deactivate() noexcept {
  if (!configured_) return;
  // Best effort and without waiting: quick stop (drives brake), disable (torque off), then
  // pre-operational (no more PDOs). Frames a full queue refuses are lost; nothing here throws.
  std::vector<hal::CanFrame> frames;
  try {
    for (auto& [name, group] : groups_) {
      frames.resize(group->size() + 1);
      for (const std::uint16_t controlword :
           {cia402::kControlQuickStop, cia402::kControlDisableVoltage}) {
        const std::size_t count = group->shutdown_frames(controlword, frames);
        (void)group->bus().send_batch(std::span(frames).first(count));
      }
      for (std::size_t k = 0; k < group->size(); ++k) {
        (void)group->bus().send(
            nmt_frame(NmtCommand::kEnterPreOperational, group->drive(k).node_id()));
      }
    }
  } catch (...) {
    // The vector's allocation is the only thing that can throw; the drives' own heartbeat
    // consumers and watchdogs cover a master that could not say goodbye.
  }
  active_ = false;
  configured_ = false;
}

void SocketCanBackend::offer(hal::BackendOffers& offers) {
  for (const auto& [name, group] : groups_) offers.offer<const CanJointGroup>(*group);
}

void register_socketcan_backend(hal::BackendFactory& factory, CanRigInfo can_rig, BusOpener opener,
                                SocketCanBackendOptions options) {
  auto shared_rig = std::make_shared<const CanRigInfo>(std::move(can_rig));
  factory.register_backend(
      SocketCanBackend::kName,
      [shared_rig, opener = std::move(opener), options = std::move(options)](
          const hal::HardwareInfo& hardware, const hal::BackendContext& context) {
        return std::unique_ptr<hal::Backend>(
            std::make_unique<SocketCanBackend>(hardware, *shared_rig, context, opener, options));
      },
      hal::BackendTraits{.paced_by_wall_clock = true},
      [shared_rig](const hal::HardwareInfo& hardware) {
        return check_can_rig(hardware, *shared_rig, SocketCanBackend::kName);
      });
}

}  // namespace cambio::canopen
