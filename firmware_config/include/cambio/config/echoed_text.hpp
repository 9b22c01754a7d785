#pragma once

// How messages repeat what a user wrote (a config value, a console word): control characters
// escaped, long text cut. Shared by the loaders and the applications' own messages.

#include <cstdio>
#include <string>
#include <string_view>

namespace cambio::config {

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

}  // namespace cambio::config
