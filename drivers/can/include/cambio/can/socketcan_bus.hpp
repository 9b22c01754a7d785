#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cambio/hal/can_bus.hpp"

namespace cambio::can {

/// One receive filter, as Linux's struct can_filter: a frame passes when
/// (frame_id & mask) == (id & mask). `id`/`mask` may carry CAN_EFF_FLAG/CAN_RTR_FLAG.
struct CanFilter {
  std::uint32_t id = 0;
  std::uint32_t mask = 0;
};

struct SocketCanOptions {
  std::string interface;           ///< "can0", "vcan0".
  bool fd = false;                 ///< CAN FD; refused with a clear message on a classic interface.
  std::vector<CanFilter> filters;  ///< Empty = receive every data frame.
  std::size_t batch_size = 64;     ///< Frames per recvmmsg/sendmmsg (1..1024).
};

/// A SocketCAN interface through one PF_CAN raw socket (Linux), implementing hal::CanBus.
///
/// - Non-blocking: send() and receive() never wait; a full transmit queue (ENOBUFS/EAGAIN) is
///   counted in status().tx_queue_full and frames_dropped and returned as kNoNewData.
/// - Batched: receive() pops from a ring filled by one recvmmsg() of up to batch_size frames
///   when it is empty; send_batch() sends with sendmmsg().
/// - Error frames (every class) are always received: they update status() (state, error
///   counters, bus_off_count; see decode_can_error_frame) and are also returned by receive()
///   with error_frame set and id = the class bits, so logs see them. Consumers of data frames
///   must skip frames with error_frame set.
/// - Timestamps: the kernel stamps each frame on arrival (SO_TIMESTAMPNS, CLOCK_REALTIME);
///   receive() returns stamp_ns on CLOCK_MONOTONIC (the realtime executor's clock), converted by
///   the offset CLOCK_REALTIME - CLOCK_MONOTONIC sampled when the batch is read (vDSO, no
///   syscall). A wall-clock step between arrival and that read shifts those frames' stamps.
/// - Kernel receive-queue overruns (SO_RXQ_OVFL) are counted in rx_overruns and frames_dropped.
/// - After open(), no call allocates. Not thread-safe: one thread (a loop) uses it.
class SocketCanBus final : public hal::CanBus {
 public:
  /// Opens and binds the socket. Throws std::runtime_error naming the interface and the cause:
  /// no kernel CAN support, no such interface, not a CAN interface, FD asked on a classic
  /// interface (MTU 16), a bad batch size.
  static std::unique_ptr<SocketCanBus> open(const SocketCanOptions& options);
  ~SocketCanBus() override;
  SocketCanBus(const SocketCanBus&) = delete;
  SocketCanBus& operator=(const SocketCanBus&) = delete;

  const std::string& name() const override;
  /// kRejected: an invalid frame (id range, length, RTR with FD) or an FD frame on a classic
  /// bus. kNoNewData: the transmit queue is full. kFault: bus-off, the interface is down, or
  /// another socket error. Error frames may be sent (the virtual rig injects them on vcan).
  hal::Status send(const hal::CanFrame& frame) override;
  hal::Status receive(hal::CanFrame& out) override;
  hal::CanBusStatus status() const override;
  std::size_t send_batch(std::span<const hal::CanFrame> frames) override;
  /// poll()s the socket: kOk when a frame is ready, kNoNewData after timeout_ns.
  hal::Status wait_for_frame(std::int64_t timeout_ns) override;

  /// Whether the socket carries CAN FD frames (options.fd on an FD interface).
  bool fd() const;
  /// The interface's MTU: 16 (classic) or 72 (CAN FD).
  int interface_mtu() const;

 private:
  struct State;
  explicit SocketCanBus(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace cambio::can
