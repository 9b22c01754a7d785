#pragma once

#include <atomic>
#include <cstdint>
#include <optional>

#include "cambio/hal/eye.hpp"
#include "cambio/hal/image.hpp"
#include "cambio/hal/status.hpp"
#include "cambio/v4l2/v4l2_capture.hpp"

namespace cambio::v4l2 {

/// How well two free-running cameras paired, written by the camera loop, read by anyone.
struct PairingCounters {
  std::atomic<std::uint64_t> pairs{0};
  std::atomic<std::int64_t> max_skew_ns{0};
  std::atomic<std::int64_t> total_skew_ns{0};  ///< Sum over pairs, for the mean.
};

/// The rig's stereo pair when both eyes are V4L2 cameras: the left eye's grab polls both
/// devices and picks the two frames to deliver by their stamps (choose_pair: at most half a
/// frame period apart, the SSM's bound); the right eye's grab in the same camera-loop cycle
/// delivers the partner. The camera loop grabs the left eye first. Real-time safe.
class V4l2StereoPair {
 public:
  V4l2StereoPair(V4l2Capture& left, V4l2Capture& right);

  hal::Status grab(hal::Eye eye, hal::Image& out) noexcept;

  std::int64_t max_skew_ns() const { return max_skew_ns_; }
  const PairingCounters& counters() const { return counters_; }

 private:
  hal::Status grab_left(hal::Image& out) noexcept;

  V4l2Capture& left_;
  V4l2Capture& right_;
  std::int64_t max_skew_ns_ = 0;
  std::optional<std::size_t> pending_right_;  // The left's partner, held for the right's grab.
  PairingCounters counters_;
};

}  // namespace cambio::v4l2
