#include "cambio/v4l2/v4l2_stereo_pair.hpp"

#include <algorithm>

#include "cambio/v4l2/frame_pairing.hpp"

namespace cambio::v4l2 {

V4l2StereoPair::V4l2StereoPair(V4l2Capture& left, V4l2Capture& right)
    : left_(left),
      right_(right),
      // Half the slower camera's period: the SSM's bound on a pair.
      max_skew_ns_(std::max(left.frame_period_ns(), right.frame_period_ns()) / 2) {}

hal::Status V4l2StereoPair::grab(hal::Eye eye, hal::Image& out) noexcept {
  if (eye == hal::Eye::kLeft) return grab_left(out);
  if (right_.faulted()) return hal::Status::kFault;
  if (!pending_right_) return hal::Status::kNoNewData;
  const std::size_t index = *pending_right_;
  pending_right_.reset();
  return right_.deliver(index, out);
}

hal::Status V4l2StereoPair::grab_left(hal::Image& out) noexcept {
  const hal::Status left_polled = left_.poll();
  const hal::Status right_polled = right_.poll();
  if (left_polled != hal::Status::kOk) return left_polled;
  // A right-eye fault is reported by the right eye's grab; the left keeps its own status.
  if (right_polled != hal::Status::kOk) return hal::Status::kNoNewData;
  const auto pair = choose_pair(left_.held_stamps_ns(), right_.held_stamps_ns(), max_skew_ns_);
  if (!pair) return hal::Status::kNoNewData;
  const hal::Status delivered = left_.deliver(pair->left, out);
  if (delivered != hal::Status::kOk) return delivered;
  pending_right_ = pair->right;
  counters_.pairs.fetch_add(1, std::memory_order_relaxed);
  counters_.total_skew_ns.fetch_add(pair->skew_ns, std::memory_order_relaxed);
  if (pair->skew_ns > counters_.max_skew_ns.load(std::memory_order_relaxed)) {
    counters_.max_skew_ns.store(pair->skew_ns, std::memory_order_relaxed);
  }
  return hal::Status::kOk;
}

}  // namespace cambio::v4l2
