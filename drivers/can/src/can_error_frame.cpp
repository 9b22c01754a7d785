#include "cambio/can/can_error_frame.hpp"

#include <linux/can.h>
#include <linux/can/error.h>

namespace cambio::can {

CanErrorFrameReport decode_can_error_frame(const hal::CanFrame& frame) noexcept {
  CanErrorFrameReport report;
  // CAN_ERR_DLC (8) is what every driver sends; a shorter frame cannot hold the status bytes.
  if (!frame.error_frame || frame.length < CAN_ERR_DLC) return report;
  report.error_class = frame.id & CAN_ERR_MASK;
  const std::uint8_t controller = frame.data[1];

  if (report.error_class & CAN_ERR_CRTL) {
    report.rx_overflow = (controller & CAN_ERR_CRTL_RX_OVERFLOW) != 0;
    report.tx_overflow = (controller & CAN_ERR_CRTL_TX_OVERFLOW) != 0;
    if (controller & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE)) {
      report.state = hal::CanBusState::kErrorPassive;
    } else if (controller & (CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING)) {
      report.state = hal::CanBusState::kErrorWarning;
    } else if (controller & CAN_ERR_CRTL_ACTIVE) {
      report.state = hal::CanBusState::kErrorActive;
    }
  }
  if (report.error_class & CAN_ERR_RESTARTED) report.state = hal::CanBusState::kErrorActive;
  if (report.error_class & CAN_ERR_BUSOFF) report.state = hal::CanBusState::kBusOff;

  if (report.error_class & (CAN_ERR_CNT | CAN_ERR_CRTL)) {
    report.tx_error_count = frame.data[6];
    report.rx_error_count = frame.data[7];
  }
  return report;
}

void apply_can_error_frame(const CanErrorFrameReport& report, hal::CanBusStatus& status) noexcept {
  ++status.error_frames;
  if (report.state) {
    if (*report.state == hal::CanBusState::kBusOff && status.state != hal::CanBusState::kBusOff) {
      ++status.bus_off_count;
    }
    status.state = *report.state;
  }
  if (report.tx_error_count) status.tx_error_count = *report.tx_error_count;
  if (report.rx_error_count) status.rx_error_count = *report.rx_error_count;
}

}  // namespace cambio::can
