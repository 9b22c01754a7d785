#pragma once

// Number and text formatting shared by the loaders' messages (internal to firmware_config).

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/config/echoed_text.hpp"

namespace cambio::config {

/// Up to 9 significant digits, no trailing zeros: 1000000 -> "1000000", 0.0002 -> "0.0002".
inline std::string format_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", value);
  return buffer;
}

/// How every message about a key that is not there begins (IssueList gathers those under a map
/// that only a `--set` made up).
inline constexpr std::string_view kMissingKey = "missing key";

/// "a, b, c": the names a message offers as choices (each echoed: see above).
inline std::string join(const std::vector<std::string>& items) {
  std::string text;
  for (const auto& item : items) text += (text.empty() ? "" : ", ") + echoed(item);
  return text;
}

}  // namespace cambio::config
