#pragma once

// The rigs `cambio can-bench` times and loads: the CANopen master (socketcan backend) and the
// virtual rig's emulated CiA 402 drives on one in-process network (no kernel CAN stack), on a
// manual clock, every frame put on the network counted.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cambio/can/in_process_can_bus.hpp"
#include "cambio/canopen/socketcan_backend.hpp"
#include "cambio/config/rig_config.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/virtual_rig/virtual_rig.hpp"

namespace cambio::app {

/// Bits a frame takes on the wire, summed over every frame any endpoint put on the network.
struct WireCount {
  std::uint64_t frames = 0;
  std::uint64_t bits = 0;
};

/// A rig of `drives` CSP drives (the pan-tilt's joints' settings) in one socketcan group on a
/// classic 1 Mbit/s bus, at a rate that bus carries within the loader's limit; the master's
/// cost per cycle does not depend on the rate.
config::RigConfig can_bench_rig(int drives);

/// The master (socketcan backend) and the virtual rig's drives on one in-process network, a
/// manual clock, stepped by the caller: configured, activated and enabled on construction.
class MasterAndDrives {
 public:
  /// Throws std::runtime_error when the drives do not reach operation enabled.
  explicit MasterAndDrives(const config::RigConfig& rig);

  /// One cycle at the next period boundary, small sines around where the joints started;
  /// returns the wall time of read + write + sync in microseconds. The drives answer after it.
  /// Throws std::runtime_error when the master's cycle fails.
  double cycle();

  const WireCount& wire() const { return wire_; }
  std::int64_t period_ns() const { return period_ns_; }
  const canopen::CanJointGroup& group() const { return *backend_->group(group_name_); }

 private:
  void let_drives_answer();
  bool all_enabled() const;

  config::RigConfig rig_;
  hal::ManualClock clock_{1'000'000'000};
  can::InProcessCanNetwork network_{false, &clock_};
  WireCount wire_;
  std::string group_name_;
  std::unique_ptr<virtual_rig::VirtualRig> drives_;
  std::unique_ptr<canopen::SocketCanBackend> backend_;
  std::unique_ptr<hal::JointGroup> group_;
  std::int64_t period_ns_ = 1'000'000;
  std::int64_t next_cycle_ns_ = 0;
  std::vector<hal::JointState> states_;
  std::vector<hal::JointCommand> commands_;
  std::vector<double> start_rad_;
};

}  // namespace cambio::app
