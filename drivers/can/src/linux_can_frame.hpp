#pragma once

// Conversion between hal::CanFrame and the kernel's struct canfd_frame (<linux/can.h>), private
// to the SocketCAN bus.
#include <linux/can.h>

#include <algorithm>
#include <cstring>

#include "cambio/hal/can_bus.hpp"

namespace cambio::can::detail {

#ifndef CANFD_FDF
#define CANFD_FDF 0x04  // Linux >= 6.0 marks FD frames with it; older headers lack it.
#endif

/// The kernel frame for `frame` (assumed valid: can_frame_problem() returned nullptr). A classic
/// frame's first CAN_MTU bytes are a struct can_frame.
inline canfd_frame to_linux_frame(const hal::CanFrame& frame) {
  canfd_frame out{};
  out.can_id = frame.id;
  if (frame.error_frame) out.can_id |= CAN_ERR_FLAG;
  if (frame.extended_id) out.can_id |= CAN_EFF_FLAG;
  if (frame.remote_request) out.can_id |= CAN_RTR_FLAG;
  out.len = frame.length;
  if (frame.fd) {
    out.flags = static_cast<__u8>((frame.bit_rate_switch ? CANFD_BRS : 0) |
                                  (frame.error_state_indicator ? CANFD_ESI : 0));
  }
  const std::size_t bytes = frame.remote_request ? 0 : frame.length;
  std::memcpy(out.data, frame.data.data(), std::min<std::size_t>(bytes, sizeof(out.data)));
  return out;
}

/// The hal frame for a kernel frame read as `fd` (its size was CANFD_MTU). The caller checks the
/// length first.
inline hal::CanFrame from_linux_frame(const canfd_frame& in, bool fd) {
  hal::CanFrame out;
  out.error_frame = (in.can_id & CAN_ERR_FLAG) != 0;
  out.extended_id = !out.error_frame && (in.can_id & CAN_EFF_FLAG) != 0;
  out.remote_request = !fd && !out.error_frame && (in.can_id & CAN_RTR_FLAG) != 0;
  out.id = out.error_frame ? (in.can_id & CAN_ERR_MASK)
                           : (in.can_id & (out.extended_id ? CAN_EFF_MASK : CAN_SFF_MASK));
  out.fd = fd;
  out.bit_rate_switch = fd && (in.flags & CANFD_BRS) != 0;
  out.error_state_indicator = fd && (in.flags & CANFD_ESI) != 0;
  out.length = in.len;
  if (!out.remote_request) std::memcpy(out.data.data(), in.data, in.len);
  return out;
}

}  // namespace cambio::can::detail
