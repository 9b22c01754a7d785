#pragma once

// Number and text formatting shared by the loaders' messages (internal to firmware_config).

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace cambio::config {

/// Up to 9 significant digits, no trailing zeros: 1000000 -> "1000000", 0.0002 -> "0.0002".
inline std::string format_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", value);
  return buffer;
}

/// `text` in double quotes, as messages show names and text values.
inline std::string in_quotes(std::string_view text) {
  return "\"" + std::string(text) + "\"";
}

/// "a, b, c": the names a message offers as choices.
inline std::string join(const std::vector<std::string>& items) {
  std::string text;
  for (const auto& item : items) text += (text.empty() ? "" : ", ") + item;
  return text;
}

}  // namespace cambio::config
