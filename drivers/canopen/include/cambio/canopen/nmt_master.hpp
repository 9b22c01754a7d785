#pragma once

// NMT master side (CiA 301 §7.2.8): module control frames, the SYNC frame, and the heartbeat
// consumer that watches one node (its NMT state, when it was last heard, loss after 3 missed
// periods, boot-up after a reboot). Header-only, no allocation: the loop side runs the consumer.
//
//   NMT module control  COB-ID 0x000, 2 bytes: command, node id (0 = every node)
//   SYNC                COB-ID 0x080, 0 bytes (no counter)
//   heartbeat/boot-up   COB-ID 0x700+node, 1 byte: NMT state (0x00 = boot-up); bit 7 is node
//                       guarding's toggle and is ignored

#include <cstdint>
#include <optional>

#include "cambio/canopen/protocol.hpp"
#include "cambio/hal/can_bus.hpp"

namespace cambio::canopen {

/// An NMT module control frame for `node_id` (0 = all nodes).
constexpr hal::CanFrame nmt_frame(NmtCommand command, int node_id) {
  hal::CanFrame frame;
  frame.id = kNmtCobId;
  frame.length = 2;
  frame.data[0] = static_cast<std::uint8_t>(command);
  frame.data[1] = static_cast<std::uint8_t>(node_id);
  return frame;
}

constexpr hal::CanFrame sync_frame() {
  hal::CanFrame frame;
  frame.id = kSyncCobId;
  frame.length = 0;
  return frame;
}

/// The NMT state a heartbeat frame carries, or nothing for a malformed one (wrong length, RTR,
/// a state CiA 301 does not define).
constexpr std::optional<NmtState> heartbeat_state(const hal::CanFrame& frame) {
  if (frame.length != 1 || frame.remote_request || frame.extended_id || frame.fd) {
    return std::nullopt;
  }
  switch (frame.data[0] & 0x7F) {
    case static_cast<std::uint8_t>(NmtState::kBootUp):
      return NmtState::kBootUp;
    case static_cast<std::uint8_t>(NmtState::kStopped):
      return NmtState::kStopped;
    case static_cast<std::uint8_t>(NmtState::kOperational):
      return NmtState::kOperational;
    case static_cast<std::uint8_t>(NmtState::kPreOperational):
      return NmtState::kPreOperational;
    default:
      return std::nullopt;
  }
}

/// Watches one node's heartbeat. Lost (latched) when no heartbeat came for more than 3 periods
/// since the last one (or since arm()); rebooted (latched) when the node sends a boot-up after it
/// was armed: its configuration is gone and it must be configured again. Not thread-safe: the
/// joint loop's thread owns it.
class HeartbeatConsumer {
 public:
  static constexpr int kMissedPeriodsForLoss = 3;

  HeartbeatConsumer() = default;
  /// `period_ns` <= 0 disables loss detection (boot-ups are still seen).
  explicit HeartbeatConsumer(std::int64_t period_ns) : period_ns_(period_ns) {}

  /// Starts watching at `now_ns`: the node has 3 periods from now to be heard.
  void arm(std::int64_t now_ns) {
    armed_ = true;
    last_heard_ns_ = now_ns;
  }
  bool armed() const { return armed_; }

  /// Records a heartbeat or boot-up with its NMT state.
  void on_heartbeat(NmtState state, std::int64_t stamp_ns) {
    state_ = state;
    heard_ = true;
    last_heard_ns_ = stamp_ns;
    if (state == NmtState::kBootUp) {
      booted_ = true;
      if (armed_) rebooted_ = true;
    }
  }

  /// Latches loss when the node has been silent for more than 3 periods. Returns lost().
  bool check(std::int64_t now_ns) {
    if (armed_ && period_ns_ > 0 && now_ns - last_heard_ns_ > kMissedPeriodsForLoss * period_ns_) {
      lost_ = true;
    }
    return lost_;
  }

  /// Clears the loss latch (a fault reset); a node that is still silent is lost again at the
  /// next check(). A reboot stays latched until the node is configured again.
  void clear_lost() { lost_ = false; }
  void clear_rebooted() { rebooted_ = false; }
  /// Forgets a boot-up seen before (the master is about to reset the node and wait for the next).
  void clear_booted() { booted_ = false; }

  bool lost() const { return lost_; }
  bool rebooted() const { return rebooted_; }
  bool booted() const { return booted_; }
  bool heard() const { return heard_; }
  NmtState state() const { return state_; }
  std::int64_t last_heard_ns() const { return last_heard_ns_; }

 private:
  std::int64_t period_ns_ = 0;
  bool armed_ = false;
  bool heard_ = false;
  bool lost_ = false;
  bool booted_ = false;
  bool rebooted_ = false;
  NmtState state_ = NmtState::kBootUp;
  std::int64_t last_heard_ns_ = 0;
};

}  // namespace cambio::canopen
