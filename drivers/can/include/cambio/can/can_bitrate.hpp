#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace cambio::can {

/// The nominal bit rate (bit/s) the OS set on a CAN interface (`ip link set can0 type can bitrate
/// 1000000`), read over rtnetlink: IFLA_LINKINFO -> IFLA_INFO_DATA -> IFLA_CAN_BITTIMING.bitrate.
/// nullopt when the interface is absent, has no bit timing (vcan, a non-CAN interface), has none
/// set yet, or the kernel cannot be asked (no netlink). Throws nothing; not for a loop.
std::optional<std::int64_t> read_can_bitrate(const std::string& interface) noexcept;

}  // namespace cambio::can
