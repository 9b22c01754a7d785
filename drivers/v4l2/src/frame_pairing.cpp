#include "cambio/v4l2/frame_pairing.hpp"

#include <algorithm>
#include <cstdlib>

namespace cambio::v4l2 {

std::optional<FramePair> choose_pair(std::span<const std::int64_t> left_ns,
                                     std::span<const std::int64_t> right_ns,
                                     std::int64_t max_skew_ns) noexcept {
  std::optional<FramePair> best;
  std::int64_t best_older_ns = 0;
  for (std::size_t l = 0; l < left_ns.size(); ++l) {
    for (std::size_t r = 0; r < right_ns.size(); ++r) {
      const std::int64_t skew_ns = std::llabs(left_ns[l] - right_ns[r]);
      if (skew_ns > max_skew_ns) continue;
      const std::int64_t older_ns = std::min(left_ns[l], right_ns[r]);
      if (!best || older_ns > best_older_ns ||
          (older_ns == best_older_ns && skew_ns < best->skew_ns)) {
        best = FramePair{l, r, skew_ns};
        best_older_ns = older_ns;
      }
    }
  }
  return best;
}

}  // namespace cambio::v4l2
