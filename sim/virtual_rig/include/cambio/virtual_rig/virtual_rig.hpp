#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cambio/canopen/can_rig.hpp"
#include "cambio/config/rig_config.hpp"
#include "cambio/hal/can_bus.hpp"
#include "cambio/hal/clock.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/virtual_rig/emulated_drive.hpp"
#include "cambio/virtual_rig/fault_injection.hpp"

namespace cambio::virtual_rig {

/// Opens the bus a rig names (SocketCanBus::open in the application, an in-process endpoint in
/// tests). Throws std::runtime_error when it cannot.
using BusOpener = std::function<std::unique_ptr<hal::CanBus>(const canopen::CanBusInfo&)>;

struct VirtualRigOptions {
  std::uint64_t seed = 1;  ///< The servos' noise: same seed, same motion.
  std::vector<FaultInjection> faults;
};

/// The drives of a rig, emulated: one EmulatedDrive per joint with CAN settings (node id, gear
/// ratio, encoder counts) of every group on `backend: socketcan` (what a master drives over CAN),
/// on that group's bus; a rig with no socketcan group gets drives for every group that names a
/// bus. Each bus is served by one thread; its drives are touched by that thread only.
class VirtualRig {
 public:
  /// Builds the drives and opens each bus once. Throws std::invalid_argument naming the group,
  /// joint or bus for a rig with no CAN joints, a group naming an unknown bus, a node id used
  /// twice on a bus or a fault for a node no bus has; whatever `open_bus` throws.
  VirtualRig(const config::RigConfig& rig, const BusOpener& open_bus,
             VirtualRigOptions options = {});

  /// Powers every drive on (boot-up messages) at `now_ns`.
  void power_on(std::int64_t now_ns);

  /// Hands every frame waiting on bus `bus` to its drives, then lets them do what is due
  /// (heartbeats, late TPDOs, faults). Returns the frames handled. Never blocks.
  std::size_t process(std::size_t bus, std::int64_t now_ns);

  /// Serves every bus (a thread each: wait for a frame or the next drive event, then process)
  /// until `stop` is set or `clock` reaches `end_ns`. Powers the drives on first.
  void run(hal::Clock& clock, const std::atomic<bool>& stop, std::int64_t end_ns);

  std::size_t bus_count() const { return buses_.size(); }
  const canopen::CanBusInfo& bus_info(std::size_t bus) const { return buses_[bus].info; }
  hal::CanBus& bus(std::size_t bus) { return *buses_[bus].bus; }
  /// The drives on bus `bus`, with the joint each emulates.
  std::size_t drive_count(std::size_t bus) const { return buses_[bus].drives.size(); }
  EmulatedDrive& drive(std::size_t bus, std::size_t k) { return *buses_[bus].drives[k]; }
  const std::string& joint_name(std::size_t bus, std::size_t k) const {
    return buses_[bus].joints[k];
  }
  /// The drive with node id `node_id` on bus `bus`, or nullptr.
  EmulatedDrive* find_drive(std::size_t bus, int node_id);

 private:
  struct Bus {
    canopen::CanBusInfo info;
    std::unique_ptr<hal::CanBus> bus;
    std::vector<std::unique_ptr<EmulatedDrive>> drives;
    std::vector<std::string> joints;
  };
  void serve(std::size_t bus, hal::Clock& clock, const std::atomic<bool>& stop,
             std::int64_t end_ns);

  std::vector<Bus> buses_;
};

}  // namespace cambio::virtual_rig
