#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "cambio/canopen/protocol.hpp"
#include "cambio/hal/can_bus.hpp"

namespace cambio::virtual_rig {

/// What an SDO server reads and writes: the device's object dictionary with the device's rules
/// on top (PDO mapping rules, controlword side effects). Every call returns 0 or an SDO abort
/// code. Real-time safe.
class SdoTarget {
 public:
  virtual ~SdoTarget() = default;
  virtual std::uint32_t sdo_read(canopen::ObjectAddress address, std::span<std::uint8_t> out,
                                 std::size_t& size) = 0;
  virtual std::uint32_t sdo_write(canopen::ObjectAddress address,
                                  std::span<const std::uint8_t> data) = 0;
  /// Bytes of the object's value (0 when it does not exist): the length an expedited download
  /// without size indication carries.
  virtual std::size_t sdo_size(canopen::ObjectAddress address) const = 0;
};

/// The default SDO server of one node (CiA 301 §7.2.4): expedited and segmented download and
/// upload, one transfer at a time. Requests arrive on 0x600 + node id, answers go out on
/// 0x580 + node id.
///
/// Frame layouts (8 data bytes each, CiA 301 §7.2.4.3):
///   initiate download  ccs=1  [001x nnes][index lo][index hi][sub][data or size (4)]
///   download segment   ccs=0  [000t nnnc][7 data bytes]
///   initiate upload    ccs=2  [0100 0000][index lo][index hi][sub][0 (4)]
///   upload segment     ccs=3  [011t 0000][0 (7)]
///   abort              cs=4   [1000 0000][index lo][index hi][sub][abort code (4, LE)]
/// e: expedited, s: size indicated, n: bytes of the 4 (or 7) that carry no data, t: toggle
/// (0 on the first segment, alternating), c: last segment. Block transfers (ccs 5, 6) are not
/// supported and are answered with "command specifier not valid".
class SdoServer {
 public:
  /// Largest value a segmented download can carry (the device's largest writable object is far
  /// smaller; larger downloads are refused with "out of memory").
  static constexpr std::size_t kMaxTransferBytes = 256;

  SdoServer(int node_id, SdoTarget& target);

  /// Handles a request frame (its id is the caller's check). Returns true and fills `response`
  /// when the server answers (an abort from the client gets no answer). Real-time safe.
  bool handle(const hal::CanFrame& request, hal::CanFrame& response) noexcept;

  /// Drops any transfer in progress (NMT reset communication, or a timeout).
  void reset() noexcept { mode_ = Mode::kIdle; }
  bool busy() const { return mode_ != Mode::kIdle; }

  /// Requests that were not 8 bytes long: counted and ignored.
  std::uint64_t malformed_requests() const { return malformed_; }

  /// Every access to `object` from now on is answered with `abort_code` (fault injection; a
  /// zero code clears it).
  void inject_abort(canopen::ObjectAddress object, std::uint32_t abort_code) noexcept {
    injected_object_ = object;
    injected_code_ = abort_code;
  }

 private:
  enum class Mode : std::uint8_t { kIdle, kDownloading, kUploading };

  void abort(hal::CanFrame& response, canopen::ObjectAddress address, std::uint32_t code) noexcept;
  bool initiate_download(const hal::CanFrame& request, hal::CanFrame& response) noexcept;
  bool download_segment(const hal::CanFrame& request, hal::CanFrame& response) noexcept;
  bool initiate_upload(const hal::CanFrame& request, hal::CanFrame& response) noexcept;
  bool upload_segment(const hal::CanFrame& request, hal::CanFrame& response) noexcept;
  std::uint32_t injected(canopen::ObjectAddress address) const noexcept {
    return injected_code_ != 0 && address == injected_object_ ? injected_code_ : 0;
  }

  int node_id_;
  SdoTarget& target_;
  Mode mode_ = Mode::kIdle;
  canopen::ObjectAddress address_{};
  std::array<std::uint8_t, kMaxTransferBytes> buffer_{};
  std::size_t size_ = 0;     ///< Bytes of the transfer (indicated or uploaded).
  std::size_t offset_ = 0;   ///< Bytes transferred so far.
  bool size_known_ = false;  ///< Download: the client indicated the size.
  std::uint8_t toggle_ = 0;  ///< The toggle bit the next segment must carry.
  std::uint64_t malformed_ = 0;
  canopen::ObjectAddress injected_object_{};
  std::uint32_t injected_code_ = 0;
};

}  // namespace cambio::virtual_rig
