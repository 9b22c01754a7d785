#pragma once

// EMCY consumer (CiA 301 §7.2.7): decodes a drive's emergency frame.
//   COB-ID 0x080+node, 8 bytes: error code (2, little-endian), error register (1 = 0x1001),
//   manufacturer-specific (5). Error code 0x0000 = "error reset or no error".
// Header-only, no allocation.

#include <optional>

#include "cambio/canopen/protocol.hpp"
#include "cambio/hal/can_bus.hpp"

namespace cambio::canopen {

/// The emergency an EMCY frame carries, or nothing for a malformed frame (CiA 301 fixes the
/// length at 8).
constexpr std::optional<Emergency> decode_emergency(const hal::CanFrame& frame) {
  if (frame.length != 8 || frame.remote_request || frame.extended_id || frame.fd) {
    return std::nullopt;
  }
  return Emergency{static_cast<std::uint16_t>(get_le(frame.data, 0, 2)), frame.data[2]};
}

/// What a master keeps of a drive's emergencies: the last error code that was not a reset,
/// kept until a fault reset (JointState::error_code's contract), and the last error register.
struct EmergencyRecord {
  std::uint16_t error_code = 0;
  std::uint8_t error_register = 0;
  std::uint64_t count = 0;

  void on_emergency(const Emergency& emergency) {
    ++count;
    error_register = emergency.error_register;
    // "Error reset" says the drive's error went away; the code stays for the operator until a
    // fault reset.
    if (emergency.error_code != 0) error_code = emergency.error_code;
  }
  void clear() {
    error_code = 0;
    error_register = 0;
  }
};

}  // namespace cambio::canopen
