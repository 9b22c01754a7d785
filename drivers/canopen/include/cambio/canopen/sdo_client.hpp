#pragma once

// SDO client (CiA 301 §7.2.4): expedited and segmented download and upload to one node, as a
// non-blocking state machine the caller feeds with the server's frames and with the time.
// No allocation and no system call: the loop side may run it (a rebooted drive's
// reconfiguration); configure time runs it through sdo_transfer.hpp's blocking helpers.
//
// Frames (8 data bytes, client -> 0x600+node, server -> 0x580+node):
//   initiate download  [001 0 n e s] idx_lo idx_hi sub d0..d3   (e: expedited, n: 4 - size)
//   download segment   [000 t n(3) c] d0..d6                     (t: toggle, c: last segment)
//   initiate upload    [010 00000] idx_lo idx_hi sub 0 0 0 0
//   upload segment     [011 t 0000] 0 ..
//   abort              [100 00000] idx_lo idx_hi sub code(4, little-endian)

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "cambio/canopen/protocol.hpp"
#include "cambio/hal/can_bus.hpp"

namespace cambio::canopen {

class SdoClient {
 public:
  enum class State : std::uint8_t {
    kIdle,     ///< No transfer started yet.
    kBusy,     ///< Waiting for the server's answer.
    kDone,     ///< The transfer completed; data() holds an upload's bytes.
    kAborted,  ///< Aborted by the server, by this client (protocol error) or by the timeout.
  };
  /// Why a transfer ended in kAborted.
  enum class Failure : std::uint8_t { kNone, kServerAbort, kClientAbort, kTimeout };

  /// The largest upload the client buffers (a device name, an EDS string).
  static constexpr std::size_t kMaxUploadBytes = 1024;

  explicit SdoClient(int node_id) : node_id_(node_id) {}

  int node_id() const { return node_id_; }

  /// Starts writing `data` (kept by the caller until the transfer ends) to `object`; expedited
  /// when it fits 4 bytes, segmented otherwise. Returns the first frame to send.
  hal::CanFrame start_download(ObjectAddress object, std::span<const std::uint8_t> data,
                               std::int64_t now_ns, std::int64_t timeout_ns);
  /// Starts reading `object`. Returns the first frame to send.
  hal::CanFrame start_upload(ObjectAddress object, std::int64_t now_ns, std::int64_t timeout_ns);

  /// Feeds one received frame. Frames that are not this node's SDO responses are ignored
  /// (returns false, `reply` untouched). Returns true when `reply` must be sent (next segment
  /// request, or the client's abort of a protocol error). Real-time safe.
  bool on_frame(const hal::CanFrame& frame, std::int64_t now_ns, hal::CanFrame& reply);

  /// Checks the answer timeout (per request, restarted by each answer). Returns true with an
  /// abort frame (0x05040000, SDO protocol timed out) in `reply` when it expired. Real-time safe.
  bool poll(std::int64_t now_ns, hal::CanFrame& reply);

  State state() const { return state_; }
  Failure failure() const { return failure_; }
  /// The abort code of a kAborted transfer (sent or received).
  std::uint32_t abort_code() const { return abort_code_; }
  ObjectAddress object() const { return object_; }
  bool is_upload() const { return upload_; }
  /// An upload's bytes once kDone.
  std::span<const std::uint8_t> data() const { return {upload_data_.data(), upload_size_}; }
  /// Writes "SDO download to 0x6060:00 aborted by the drive: 0x06090030 (value range
  /// of parameter exceeded)" into `out` (NUL-terminated, cut to fit) for a kAborted transfer.
  /// Real-time safe.
  void describe_failure(std::span<char> out) const;

 private:
  hal::CanFrame request_frame() const;
  hal::CanFrame next_download_segment();
  bool abort(std::uint32_t code, hal::CanFrame& reply);
  SdoAbortCode initiate_mismatch(const hal::CanFrame& frame, std::uint8_t expected_scs) const;
  bool on_download_answer(const hal::CanFrame& frame, hal::CanFrame& reply);
  bool on_upload_answer(const hal::CanFrame& frame, hal::CanFrame& reply);
  bool append(std::span<const std::uint8_t> bytes);

  int node_id_;
  State state_ = State::kIdle;
  Failure failure_ = Failure::kNone;
  bool upload_ = false;
  bool initiated_ = false;  ///< The initiate request was answered; segments follow.
  bool toggle_ = false;     ///< The toggle bit of the next segment.
  ObjectAddress object_{};
  std::uint32_t abort_code_ = 0;
  std::int64_t deadline_ns_ = 0;
  std::int64_t timeout_ns_ = 0;
  std::span<const std::uint8_t> download_data_{};
  std::size_t download_offset_ = 0;
  std::array<std::uint8_t, kMaxUploadBytes> upload_data_{};
  std::size_t upload_size_ = 0;
  std::size_t upload_expected_ = 0;  ///< The size the server announced; 0 = not announced.
  bool upload_size_known_ = false;
};

}  // namespace cambio::canopen
