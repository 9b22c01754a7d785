#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace cambio::app {

/// What this machine says about a CAN interface a rig names, for `cambio check-config`.
struct CanInterfaceBitrate {
  bool present = false;  ///< The interface exists here (/sys/class/net/<interface>).
  /// Its nominal bit rate as the kernel reports it; nullopt when it reports none (vcan has no bit
  /// timing) or the query is unavailable.
  std::optional<std::int64_t> bitrate_bit_s;
};

/// Looks `interface` up on this machine. `interface` must be a valid interface name (the rig
/// loader checks it). Never throws.
CanInterfaceBitrate query_can_interface_bitrate(const std::string& interface);

}  // namespace cambio::app
