#include "cambio/v4l2/stamp_mapping.hpp"

#include <ctime>

namespace cambio::v4l2 {

std::int64_t monotonic_now_ns() noexcept {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

}  // namespace cambio::v4l2
