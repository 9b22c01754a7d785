#include "cambio/runtime/scheduled_loop.hpp"

#include <cmath>

namespace cambio::runtime {

std::int64_t deadline_ns(std::int64_t start_ns, std::uint64_t k, double rate_hz) {
  // Long double keeps k * 1e9 exact far beyond any run length (k < 2^53 / 1e9 would already
  // hold for double at 1 kHz for ~100 days; this keeps margin for higher rates).
  const long double offset = static_cast<long double>(k) * 1e9L / static_cast<long double>(rate_hz);
  return start_ns + static_cast<std::int64_t>(std::llround(offset));
}

}  // namespace cambio::runtime
