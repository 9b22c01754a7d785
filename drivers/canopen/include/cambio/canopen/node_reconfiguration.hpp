#pragma once

// Configuring a rebooted drive again while the joint loop runs (a boot-up after NMT start: the
// drive lost its parameters and PDO mapping). The steps are those configure() took: the same SDO
// writes in the same order (drive parameters, then the PDO configuration), the same read-back
// (the last write to each object, where marked verify), the statusword and position read to seed
// the drive's feedback, then NMT start.
//
// The plan is built at configure (it allocates); NodeReconfiguration runs it on the loop side,
// one SDO exchange in flight at a time, with the non-blocking SdoClient: no allocation, no lock,
// no blocking. It never sends itself: the joint group takes its one pending frame into the
// cycle's batched send and feeds it the node's SDO answers.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "cambio/canopen/object_write.hpp"
#include "cambio/canopen/pdo_codec.hpp"
#include "cambio/canopen/sdo_client.hpp"
#include "cambio/hal/can_bus.hpp"

namespace cambio::canopen {

struct ReconfigurationStep {
  enum class Kind : std::uint8_t { kWrite, kVerify, kReadStatusword, kReadPosition, kNmtStart };
  Kind kind = Kind::kWrite;
  ObjectWrite write{};  ///< The object and value written (kWrite) or expected (kVerify).
};

/// `writes` in order, then a kVerify per object as verify_objects() checks them, then the
/// statusword and position reads, then NMT start.
std::vector<ReconfigurationStep> reconfiguration_plan(std::span<const ObjectWrite> writes);

/// Why a reconfiguration failed: fixed size, so the loop side fills it without allocating and
/// another thread reads it through a SeqlockChannel.
struct ReconfigurationError {
  std::int32_t node_id = 0;
  std::uint32_t abort_code = 0;  ///< The SDO abort code (sent or received); 0 for a mismatch.
  /// e.g. "node 10: SDO download to 0x6060:00 aborted by the drive: 0x06090030 (value range of
  /// parameter exceeded)" or "node 10: object 0x607D:02 written 32595 (0x00007F53), read back
  /// 1000 (0x000003E8)". NUL-terminated.
  std::array<char, 192> text{};
};

class NodeReconfiguration {
 public:
  enum class State : std::uint8_t { kIdle, kRunning, kDone, kFailed };

  /// Starts replaying `plan` (kept by the caller while it runs) on `node_id`; each SDO request
  /// waits at most `timeout_ns` for its answer. Real-time safe.
  void start(int node_id, std::span<const ReconfigurationStep> plan, std::int64_t timeout_ns,
             std::int64_t now_ns);
  /// Ends a running reconfiguration as failed with `reason` (e.g. the node booted again).
  void fail(const char* reason);

  /// The frame to send next, if any: an SDO request, the client's abort, or NMT start.
  bool has_pending() const { return pending_; }
  const hal::CanFrame& pending_frame() const { return pending_frame_; }
  /// The pending frame went out.
  void on_sent(std::int64_t now_ns);
  /// An SDO response from the node (0x580 + node id).
  void on_frame(const hal::CanFrame& frame, std::int64_t now_ns);
  /// Checks the SDO answer timeout.
  void poll(std::int64_t now_ns);

  State state() const { return state_; }
  int node_id() const { return client_.node_id(); }
  /// The statusword and position read during the run (valid once kDone).
  const DriveFeedback& feedback() const { return feedback_; }
  /// Why it failed (valid once kFailed).
  const ReconfigurationError& error() const { return error_; }

 private:
  void begin_step(std::int64_t now_ns);
  void finish_step(std::int64_t now_ns);
  void fail_sdo();
  void set_pending(const hal::CanFrame& frame) {
    pending_frame_ = frame;
    pending_ = true;
  }

  SdoClient client_{0};
  std::span<const ReconfigurationStep> plan_{};
  std::size_t step_ = 0;
  std::int64_t timeout_ns_ = 0;
  State state_ = State::kIdle;
  bool pending_ = false;
  hal::CanFrame pending_frame_{};
  std::array<std::uint8_t, 4> download_{};
  DriveFeedback feedback_{};
  ReconfigurationError error_{};
};

}  // namespace cambio::canopen
