#pragma once

#include <cstdint>

#include "cambio/hal/can_bus.hpp"

namespace cambio::can {

/// Whether `length` is a CAN FD data length (ISO 11898-1: 0-8, 12, 16, 20, 24, 32, 48, 64).
constexpr bool is_can_fd_length(std::uint8_t length) {
  return length <= 8 || length == 12 || length == 16 || length == 20 || length == 24 ||
         length == 32 || length == 48 || length == 64;
}

/// Why `frame` cannot go on a bus (`fd_bus`: the bus carries CAN FD), or nullptr if it can:
/// identifier range, data length, flags that contradict each other. Real-time safe.
constexpr const char* can_frame_problem(const hal::CanFrame& frame, bool fd_bus) {
  if (frame.fd && !fd_bus) return "CAN FD frame on a classic CAN bus";
  if (frame.fd && frame.remote_request) return "CAN FD has no remote frames";
  if (!frame.fd && (frame.bit_rate_switch || frame.error_state_indicator)) {
    return "BRS/ESI flags on a classic frame";
  }
  if (frame.error_frame) {
    if (frame.fd || frame.remote_request || frame.extended_id) {
      return "an error frame is classic, with no RTR or extended flag";
    }
    if (frame.id > 0x1FFF'FFFFu) return "error class bits beyond CAN_ERR_MASK";
  } else if (frame.id > (frame.extended_id ? 0x1FFF'FFFFu : 0x7FFu)) {
    return frame.extended_id ? "extended identifier above 0x1FFFFFFF"
                             : "standard identifier above 0x7FF";
  }
  if (frame.fd ? !is_can_fd_length(frame.length)
               : frame.length > hal::CanFrame::kMaxClassicDataBytes) {
    return frame.fd ? "not a CAN FD data length" : "more than 8 data bytes in a classic frame";
  }
  return nullptr;
}

}  // namespace cambio::can
