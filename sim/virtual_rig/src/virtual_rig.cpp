#include "cambio/virtual_rig/virtual_rig.hpp"

#include <algorithm>
#include <stdexcept>
#include <thread>

#include "cambio/canopen/can_rig_from_config.hpp"
#include "cambio/config/hardware_description.hpp"

namespace cambio::virtual_rig {

namespace {

/// The longest a bus thread waits before it looks at the stop flag again.
constexpr std::int64_t kMaxWaitNs = 10'000'000;
/// Frames handled per pass before the drives' timers get a turn.
constexpr std::size_t kMaxFramesPerPass = 256;

}  // namespace

VirtualRig::VirtualRig(const config::RigConfig& rig, const BusOpener& open_bus,
                       VirtualRigOptions options) {
  const hal::HardwareInfo hardware = config::hardware_description(rig);
  const canopen::CanRigInfo can_rig = canopen::can_rig_from_config(rig);
  const double step_s = 1.0 / rig.sim.physics_rate_hz;
  // The groups a master drives over CAN are those the rig puts on socketcan; a rig with none
  // (as shipped, all on the sim) gets a drive for every group that names a bus. So the virtual
  // rig and `cambio run` take the same rig file and the same --set overrides.
  const bool any_socketcan =
      std::any_of(hardware.groups.begin(), hardware.groups.end(),
                  [](const hal::JointGroupInfo& group) { return group.backend == "socketcan"; });
  for (const auto& group : hardware.groups) {
    const canopen::CanGroupInfo& can_group = *can_rig.find_group(group.name);
    if (can_group.bus.empty()) continue;
    if (any_socketcan && group.backend != "socketcan") continue;
    const canopen::CanBusInfo* info = can_rig.find_bus(can_group.bus);
    if (info == nullptr) {
      throw std::invalid_argument("virtual rig: group " + group.name + " names CAN bus '" +
                                  can_group.bus + "', which can_buses does not define");
    }
    auto bus = std::find_if(buses_.begin(), buses_.end(),
                            [&](const Bus& b) { return b.info.name == info->name; });
    if (bus == buses_.end()) {
      std::unique_ptr<hal::CanBus> opened = open_bus(*info);
      if (!opened) throw std::runtime_error("virtual rig: could not open CAN bus " + info->name);
      buses_.push_back(Bus{*info, std::move(opened), {}, {}});
      bus = buses_.end() - 1;
    }
    for (const auto& joint_name : group.joints) {
      const hal::JointInfo* joint = hardware.find_joint(joint_name);
      const config::JointConfig* joint_config = rig.find_joint(joint_name);
      const canopen::JointDriveInfo* drive_info = can_rig.find_drive(joint_name);
      if (joint == nullptr || joint_config == nullptr || drive_info == nullptr) continue;
      const canopen::JointDriveInfo& drive = *drive_info;
      for (const auto& other : bus->drives) {
        if (other->node_id() == drive.node_id) {
          throw std::invalid_argument("virtual rig: joint " + joint_name + " has node id " +
                                      std::to_string(drive.node_id) + ", already used on bus " +
                                      info->name);
        }
      }
      EmulatedDriveConfig config;
      config.node_id = drive.node_id;
      config.servo = sim::ServoParams::from_joint(*joint_config, step_s);
      // One noise stream per node: the same rig and seed move the same way every run.
      config.seed =
          options.seed * 0x9E37'79B9'7F4A'7C15ULL + static_cast<std::uint64_t>(drive.node_id);
      config.initial_position_rad = joint->initial_position_rad;
      config.gear_ratio = drive.gear_ratio;
      config.encoder_counts_per_rev = drive.encoder_counts_per_rev;
      config.following_error_window_rad = drive.following_error_window_rad;
      config.heartbeat_period_s = can_group.settings.heartbeat_period_s;
      config.mode = drive.mode;
      if (joint->limits.max_effort_nm > 0.0) config.rated_torque_nm = joint->limits.max_effort_nm;
      if (joint_config->can) {
        config.home_switch_rad = joint_config->can->virtual_home_switch_rad;
        config.index_pulse_rad = joint_config->can->virtual_index_pulse_rad.value_or(0.0);
      }
      bus->drives.push_back(std::make_unique<EmulatedDrive>(config, *bus->bus));
      bus->joints.push_back(joint_name);
    }
  }
  std::size_t drives = 0;
  for (const auto& bus : buses_) drives += bus.drives.size();
  if (drives == 0) {
    throw std::invalid_argument("virtual rig: rig " + rig.name +
                                " has no joint with CAN settings (joints.<j>.can) in a group "
                                "with a can_bus");
  }
  for (const auto& fault : options.faults) {
    bool taken = false;
    for (auto& bus : buses_) {
      for (auto& drive : bus.drives) {
        if (fault.node_id != 0 && fault.node_id != drive->node_id()) continue;
        if (!drive->schedule(fault)) {
          throw std::invalid_argument(
              "virtual rig: node " + std::to_string(drive->node_id()) + " has more than " +
              std::to_string(EmulatedDrive::kMaxScheduledFaults) + " faults scheduled");
        }
        taken = true;
      }
    }
    if (!taken) {
      throw std::invalid_argument("virtual rig: fault for node " + std::to_string(fault.node_id) +
                                  ", which no CAN bus of the rig has (" + describe(fault) + ")");
    }
  }
}

void VirtualRig::power_on(std::int64_t now_ns) {
  for (auto& bus : buses_) {
    for (auto& drive : bus.drives) drive->power_on(now_ns);
  }
}

std::size_t VirtualRig::process(std::size_t b, std::int64_t now_ns) {
  Bus& bus = buses_[b];
  std::size_t handled = 0;
  hal::CanFrame frame;
  while (handled < kMaxFramesPerPass && bus.bus->receive(frame) == hal::Status::kOk) {
    for (auto& drive : bus.drives) drive->handle(frame, now_ns);
    ++handled;
  }
  for (auto& drive : bus.drives) drive->poll(now_ns);
  return handled;
}

EmulatedDrive* VirtualRig::find_drive(std::size_t b, int node_id) {
  for (auto& drive : buses_[b].drives) {
    if (drive->node_id() == node_id) return drive.get();
  }
  return nullptr;
}

void VirtualRig::serve(std::size_t b, hal::Clock& clock, const std::atomic<bool>& stop,
                       std::int64_t end_ns) {
  Bus& bus = buses_[b];
  while (!stop.load(std::memory_order_relaxed)) {
    const std::int64_t now_ns = clock.now_ns();
    if (now_ns >= end_ns) return;
    std::int64_t next_ns = end_ns;
    for (const auto& drive : bus.drives) next_ns = std::min(next_ns, drive->next_event_ns());
    const std::int64_t wait_ns = std::clamp<std::int64_t>(next_ns - now_ns, 0, kMaxWaitNs);
    if (wait_ns > 0) (void)bus.bus->wait_for_frame(wait_ns);
    process(b, clock.now_ns());
  }
}

void VirtualRig::run(hal::Clock& clock, const std::atomic<bool>& stop, std::int64_t end_ns) {
  power_on(clock.now_ns());
  std::vector<std::thread> threads;
  for (std::size_t b = 1; b < buses_.size(); ++b) {
    threads.emplace_back([this, b, &clock, &stop, end_ns] { serve(b, clock, stop, end_ns); });
  }
  serve(0, clock, stop, end_ns);
  for (auto& thread : threads) thread.join();
}

}  // namespace cambio::virtual_rig
