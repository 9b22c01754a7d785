#pragma once

#include <cstddef>
#include <istream>
#include <string>

namespace cambio::app {

/// The longest input line a command reads (console scripts, fault files): far beyond any command
/// a person types, and a bound on what an endless line (`< /dev/zero`) can make the program hold.
inline constexpr std::size_t kMaxInputLineChars = 4096;

enum class LineRead { kLine, kEnd, kTooLong };

/// Reads one line (without its '\n') of at most `max_chars` characters, as std::getline does
/// (a last line without '\n' is a line). kTooLong: the line went past `max_chars`; nothing more
/// of the stream is read, so an endless line costs no more than `max_chars`.
inline LineRead read_bounded_line(std::istream& in, std::string& line,
                                  std::size_t max_chars = kMaxInputLineChars) {
  line.clear();
  for (;;) {
    const std::istream::int_type c = in.get();
    if (c == std::istream::traits_type::eof())
      return line.empty() ? LineRead::kEnd : LineRead::kLine;
    if (c == '\n') return LineRead::kLine;
    if (line.size() >= max_chars) return LineRead::kTooLong;
    line.push_back(static_cast<char>(c));
  }
}

}  // namespace cambio::app
