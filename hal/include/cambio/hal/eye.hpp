#pragma once

#include <cstdint>
#include <string_view>

namespace cambio::hal {

/// One eye of a stereo head. The values index per-eye arrays (left first), as in the perception
/// frames and summaries.
enum class Eye : std::uint8_t { kLeft = 0, kRight = 1 };

/// The eye across: the dominant eye of a verging one, and back.
constexpr Eye other(Eye eye) {
  return eye == Eye::kLeft ? Eye::kRight : Eye::kLeft;
}

/// "left" or "right", as config files and messages spell it.
constexpr std::string_view to_string(Eye eye) {
  return eye == Eye::kLeft ? "left" : "right";
}

}  // namespace cambio::hal
