#pragma once

#include <cstdint>
#include <optional>

#include "cambio/hal/can_bus.hpp"

namespace cambio::can {

/// What one SocketCAN error frame says about the controller, decoded per <linux/can/error.h>:
/// the frame's id holds the error class bits (CAN_ERR_CRTL, CAN_ERR_BUSOFF, ...), data[1] the
/// controller status (warning/passive per direction, back to active), data[6]/data[7] the
/// transmit/receive error counters.
struct CanErrorFrameReport {
  std::uint32_t error_class = 0;  ///< The CAN_ERR_* class bits of the id.
  /// The controller state the frame reports, if it reports one. Bus-off wins over the controller
  /// status byte; CAN_ERR_RESTARTED and CAN_ERR_CRTL_ACTIVE mean error active again.
  std::optional<hal::CanBusState> state;
  /// Error counters (ISO 11898-1 TEC/REC), when the frame carries them: CAN_ERR_CNT set, or a
  /// controller-status frame (CAN_ERR_CRTL), where drivers fill them without that flag.
  std::optional<std::uint8_t> tx_error_count;
  std::optional<std::uint8_t> rx_error_count;
  bool rx_overflow = false;  ///< The controller's receive buffer overflowed (frames lost).
  bool tx_overflow = false;  ///< The controller's transmit buffer overflowed.
};

/// Decodes an error frame (`frame.error_frame`; `frame.id` holds the class bits without
/// CAN_ERR_FLAG). A frame that is not an error frame, or is too short for the bytes its class
/// bits announce, yields an empty report (no state, no counters): never trusted. Real-time safe.
CanErrorFrameReport decode_can_error_frame(const hal::CanFrame& frame) noexcept;

/// Applies a report to a bus status: state, counters, error_frames, bus_off_count (counted on the
/// transition into bus-off). Real-time safe.
void apply_can_error_frame(const CanErrorFrameReport& report, hal::CanBusStatus& status) noexcept;

}  // namespace cambio::can
