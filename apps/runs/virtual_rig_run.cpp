#include "virtual_rig_run.hpp"

#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <stdexcept>

#include "cambio/can/socketcan_bus.hpp"
#include "cambio/hal/monotonic_clock.hpp"
#include "command.hpp"
#include "peak_rss.hpp"
#include "stop_signal.hpp"

namespace cambio::app {

namespace {

/// The one place the virtual rig meets the kernel's CAN stack.
std::unique_ptr<hal::CanBus> open_socketcan_bus(const canopen::CanBusInfo& info) {
  can::SocketCanOptions options;
  options.interface = info.interface;
  options.fd = info.fd;
  return can::SocketCanBus::open(options);
}

void print_layout(virtual_rig::VirtualRig& emulated,
                  const virtual_rig::VirtualRigOptions& options) {
  for (std::size_t b = 0; b < emulated.bus_count(); ++b) {
    std::cout << "bus " << emulated.bus_info(b).name << " on "
              << emulated.bus_info(b).interface << ":";
    for (std::size_t k = 0; k < emulated.drive_count(b); ++k) {
      std::cout << " node " << emulated.drive(b, k).node_id() << " (" << emulated.joint_name(b, k)
                << ")";
    }
    std::cout << "\n";
  }
  for (const auto& fault : options.faults) std::cout << "fault: " << describe(fault) << "\n";
  std::cout << std::flush;
}

void print_drive_counters(virtual_rig::VirtualRig& emulated) {
  for (std::size_t b = 0; b < emulated.bus_count(); ++b) {
    for (std::size_t k = 0; k < emulated.drive_count(b); ++k) {
      const auto& drive = emulated.drive(b, k);
      const auto& c = drive.counters();
      std::printf(
          "node %d (%s): %llu SYNCs, %llu RPDOs, %llu TPDOs sent, %llu dropped, %llu late, "
          "%llu EMCY, %llu heartbeats, %llu malformed frames, %llu send failures\n",
          drive.node_id(), emulated.joint_name(b, k).c_str(),
          static_cast<unsigned long long>(c.syncs), static_cast<unsigned long long>(c.rpdos),
          static_cast<unsigned long long>(c.tpdos_sent),
          static_cast<unsigned long long>(c.tpdos_dropped),
          static_cast<unsigned long long>(c.tpdos_late),
          static_cast<unsigned long long>(c.emergencies),
          static_cast<unsigned long long>(c.heartbeats),
          static_cast<unsigned long long>(c.malformed_frames),
          static_cast<unsigned long long>(c.send_failures));
    }
  }
}

}  // namespace

int run_virtual_rig(const config::RigConfig& rig, const virtual_rig::VirtualRigOptions& options,
                    double duration_s) {
  std::unique_ptr<virtual_rig::VirtualRig> emulated;
  try {
    emulated = std::make_unique<virtual_rig::VirtualRig>(rig, &open_socketcan_bus, options);
  } catch (const std::invalid_argument& error) {
    // The rig or the faults asked for something the emulation cannot be.
    std::cerr << "cambio virtual-rig: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& error) {
    // A bus that cannot be opened (no SocketCAN in the kernel, no interface): a device fault, as
    // for `cambio run` and `cambio console` on the same machine.
    std::cerr << "cambio virtual-rig: " << error.what() << "\n";
    return kExitDeviceFault;
  }
  print_layout(*emulated, options);

  const auto& stop = install_stop_signal_handlers();
  hal::MonotonicClock clock;
  const std::int64_t end_ns = duration_s > 0.0
                                  ? clock.now_ns() + static_cast<std::int64_t>(duration_s * 1e9)
                                  : std::numeric_limits<std::int64_t>::max();
  emulated->run(clock, stop, end_ns);

  print_drive_counters(*emulated);
  std::printf("virtual-rig: peak RSS %ld KiB\n", peak_rss_kib());
  const int signal_number = stop_signal_number();
  return signal_number != 0 ? exit_status_for_signal(signal_number) : kExitOk;
}

}  // namespace cambio::app
