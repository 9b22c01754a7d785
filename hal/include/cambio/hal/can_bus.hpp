#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "cambio/hal/status.hpp"

namespace cambio::hal {

/// One CAN frame, classic or FD. Fixed size so frames move without allocation.
/// Byte layout on the wire follows Linux <linux/can.h>: `id` holds the 11- or 29-bit identifier
/// (no flag bits); the flags are separate fields here.
struct CanFrame {
  static constexpr std::uint8_t kMaxClassicDataBytes = 8;
  static constexpr std::uint8_t kMaxFdDataBytes = 64;

  std::uint32_t id = 0;
  bool extended_id = false;     ///< 29-bit identifier.
  bool remote_request = false;  ///< RTR (classic only).
  bool error_frame = false;     ///< Error frame reported by the controller; `data` holds its class.
  bool fd = false;              ///< CAN FD frame (up to 64 data bytes).
  bool bit_rate_switch = false;        ///< FD BRS: data phase at the data bit rate.
  bool error_state_indicator = false;  ///< FD ESI: the transmitter was error passive.
  std::uint8_t length = 0;             ///< Data bytes (0-8 classic; FD: 0-8,12,16,20,24,32,48,64).
  std::array<std::uint8_t, kMaxFdDataBytes> data{};
  std::int64_t stamp_ns = 0;  ///< Receive time (kernel timestamp where available).
};

/// Controller state per ISO 11898-1 fault confinement.
enum class CanBusState : std::uint8_t {
  kErrorActive,
  kErrorWarning,
  kErrorPassive,
  kBusOff,
  kDown
};

struct CanBusStatus {
  CanBusState state = CanBusState::kDown;
  std::uint16_t tx_error_count = 0;
  std::uint16_t rx_error_count = 0;
  std::uint64_t frames_sent = 0;
  std::uint64_t frames_received = 0;
  std::uint64_t frames_dropped = 0;    ///< Send queue full or receive overruns.
  std::uint64_t tx_queue_full = 0;     ///< Sends refused: the kernel's transmit queue was full.
  std::uint64_t rx_overruns = 0;       ///< Frames the kernel dropped before we read them.
  std::uint64_t error_frames = 0;      ///< Error frames received from the controller.
  std::uint64_t bus_off_count = 0;     ///< Times the controller went bus-off.
  std::uint64_t malformed_frames = 0;  ///< Received frames that could not be decoded (ignored).
};

/// A CAN interface (SocketCAN, or the in-process bus used in unit tests).
class CanBus {
 public:
  virtual ~CanBus() = default;
  virtual const std::string& name() const = 0;
  /// Queues one frame without blocking: kOk, kRejected (bad frame, e.g. FD on a classic bus),
  /// kNoNewData (transmit queue full; retry next cycle), kFault (bus-off or down). Real-time safe.
  virtual Status send(const CanFrame& frame) = 0;
  /// Takes one received frame without blocking: kOk, or kNoNewData if none is queued.
  /// Real-time safe.
  virtual Status receive(CanFrame& out) = 0;
  /// Error counters and bus state. Real-time safe.
  virtual CanBusStatus status() const = 0;

  /// Queues frames in order, stopping at the first that is not accepted; returns how many were.
  /// A SocketCAN bus sends them with one system call (sendmmsg). Real-time safe.
  virtual std::size_t send_batch(std::span<const CanFrame> frames) {
    std::size_t sent = 0;
    while (sent < frames.size() && send(frames[sent]) == Status::kOk) ++sent;
    return sent;
  }

  /// Blocks until a frame can be received or `timeout_ns` passes: kOk when one is ready,
  /// kNoNewData on timeout. For processes that wait on the bus (the virtual rig's drives), never
  /// for a loop.
  virtual Status wait_for_frame(std::int64_t timeout_ns) {
    (void)timeout_ns;
    return Status::kNoNewData;
  }
};

}  // namespace cambio::hal
