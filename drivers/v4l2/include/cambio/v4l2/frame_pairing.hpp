#pragma once

#include <cstdint>
#include <optional>
#include <span>

namespace cambio::v4l2 {

/// Indices into the two eyes' held frames and how far apart their stamps are.
struct FramePair {
  std::size_t left = 0;
  std::size_t right = 0;
  std::int64_t skew_ns = 0;
};

/// Pairs two free-running cameras by their stamps (ns, run clock): among the frames each eye
/// holds, the pair whose older frame is newest, of those at most `max_skew_ns` apart (half a
/// frame period: the SSM refuses wider pairs); among pairs as new, the closest. The cameras
/// requeue what they delivered, so no frame is paired twice. nullopt when no pair qualifies.
/// Real-time safe: no allocation, O(left x right).
std::optional<FramePair> choose_pair(std::span<const std::int64_t> left_ns,
                                     std::span<const std::int64_t> right_ns,
                                     std::int64_t max_skew_ns) noexcept;

}  // namespace cambio::v4l2
