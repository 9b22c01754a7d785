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

/// How every message about a key that is not there begins (IssueList gathers those under a map
/// that only a `--set` made up).
inline constexpr std::string_view kMissingKey = "missing key";

/// The most characters of a value, name or key a message repeats: enough to recognise it, and a
/// 1 MB value does not bury the message (or the terminal) under itself.
inline constexpr std::size_t kMaxEchoedChars = 80;

/// `text` as a message repeats it: control characters escaped (so one problem stays on one line)
/// and, past `max_chars` characters (UTF-8 code points, never cut inside one), cut with "..."
/// and its full size in bytes.
inline std::string echoed(std::string_view text, std::size_t max_chars = kMaxEchoedChars) {
  std::string out;
  std::size_t chars = 0;
  std::size_t i = 0;
  for (; i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    const bool continues_char = (byte & 0xC0) == 0x80;
    if (!continues_char && chars++ == max_chars) break;
    if (byte == '\n') {
      out += "\\n";
    } else if (byte == '\t') {
      out += "\\t";
    } else if (byte < 0x20 || byte == 0x7F) {
      char escape[8];
      std::snprintf(escape, sizeof escape, "\\x%02x", byte);
      out += escape;
    } else {
      out += static_cast<char>(byte);
    }
  }
  if (i < text.size()) out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

/// `text` in double quotes, as messages show names and text values (echoed: see above).
inline std::string in_quotes(std::string_view text) {
  return "\"" + echoed(text) + "\"";
}

/// "a, b, c": the names a message offers as choices (each echoed: see above).
inline std::string join(const std::vector<std::string>& items) {
  std::string text;
  for (const auto& item : items) text += (text.empty() ? "" : ", ") + echoed(item);
  return text;
}

}  // namespace cambio::config
