#pragma once

#include <cstdint>

namespace cambio::v4l2 {

/// Maps a driver's capture stamps (CLOCK_MONOTONIC, V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC: the time
/// the frame's first byte arrived) onto the run's clock, by the offset between the two read
/// back to back when streaming starts. Under the realtime executor the run's clock is
/// CLOCK_MONOTONIC and the offset is the read-out gap (< 1 us); under a clock of another epoch
/// the stamps keep their spacing. Real-time safe.
class StampMapping {
 public:
  /// `run_now_ns` and `monotonic_now_ns` read as close together as possible.
  void anchor(std::int64_t run_now_ns, std::int64_t monotonic_now_ns) {
    offset_ns_ = run_now_ns - monotonic_now_ns;
  }
  std::int64_t to_run_ns(std::int64_t monotonic_ns) const { return monotonic_ns + offset_ns_; }
  std::int64_t offset_ns() const { return offset_ns_; }

 private:
  std::int64_t offset_ns_ = 0;
};

/// CLOCK_MONOTONIC now (ns). Real-time safe (vDSO).
std::int64_t monotonic_now_ns() noexcept;

}  // namespace cambio::v4l2
