#include "cambio/can/candump_log.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "cambio/can/can_frame_rules.hpp"

namespace cambio::can {
namespace {

constexpr char kHexUpper[] = "0123456789ABCDEF";
constexpr std::uint32_t kErrFlag = 0x2000'0000;  // CAN_ERR_FLAG, <linux/can.h>
constexpr std::uint8_t kFdFlagBrs = 0x01;        // CANFD_BRS
constexpr std::uint8_t kFdFlagEsi = 0x02;        // CANFD_ESI
constexpr std::uint8_t kFdFlagFdf = 0x04;        // CANFD_FDF
constexpr std::size_t kMaxInterfaceChars = 15;   // IFNAMSIZ - 1

char* put_hex(char* out, std::uint32_t value, int digits) {
  for (int i = digits - 1; i >= 0; --i) *out++ = kHexUpper[(value >> (4 * i)) & 0xF];
  return out;
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

[[noreturn]] void parse_error(std::size_t column, const std::string& what) {
  throw CandumpParseError("column " + std::to_string(column + 1) + ": " + what);
}

}  // namespace

std::size_t format_candump_frame(const hal::CanFrame& frame, std::span<char> out) noexcept {
  if (out.size() < kMaxCandumpFrameChars) return 0;
  char* p = out.data();
  if (frame.error_frame) {
    p = put_hex(p, kErrFlag | (frame.id & 0x1FFF'FFFF), 8);
  } else if (frame.extended_id) {
    p = put_hex(p, frame.id & 0x1FFF'FFFF, 8);
  } else {
    p = put_hex(p, frame.id & 0x7FF, 3);
  }
  *p++ = '#';
  if (frame.remote_request && !frame.fd && !frame.error_frame) {
    *p++ = 'R';
    if (frame.length > 0 && frame.length <= hal::CanFrame::kMaxClassicDataBytes) {
      *p++ = kHexUpper[frame.length];
    }
    return static_cast<std::size_t>(p - out.data());
  }
  std::size_t length = frame.length;
  if (frame.fd) {
    *p++ = '#';
    *p++ = kHexUpper[kFdFlagFdf | (frame.bit_rate_switch ? kFdFlagBrs : 0) |
                     (frame.error_state_indicator ? kFdFlagEsi : 0)];
    length = std::min<std::size_t>(length, hal::CanFrame::kMaxFdDataBytes);
  } else {
    length = std::min<std::size_t>(length, hal::CanFrame::kMaxClassicDataBytes);
  }
  for (std::size_t i = 0; i < length; ++i) p = put_hex(p, frame.data[i], 2);
  return static_cast<std::size_t>(p - out.data());
}

std::string format_candump_frame(const hal::CanFrame& frame) {
  char buffer[kMaxCandumpFrameChars];
  return std::string(buffer, format_candump_frame(frame, buffer));
}

std::size_t format_candump_line(std::int64_t wall_time_us, std::string_view interface,
                                const hal::CanFrame& frame, std::span<char> out) noexcept {
  if (out.size() < kMaxCandumpLineChars) return 0;
  const std::int64_t us = std::max<std::int64_t>(wall_time_us, 0);
  const std::string_view name = interface.substr(0, kMaxInterfaceChars);
  // lib.c/candump.c: "(%010lu.%06lu) %s %s\n".
  const int head = std::snprintf(
      out.data(), out.size(), "(%010lld.%06lld) %.*s ", static_cast<long long>(us / 1'000'000),
      static_cast<long long>(us % 1'000'000), static_cast<int>(name.size()), name.data());
  if (head < 0) return 0;
  std::size_t length = static_cast<std::size_t>(head);
  length += format_candump_frame(frame, out.subspan(length));
  out[length++] = '\n';
  return length;
}

std::string format_candump_line(std::int64_t wall_time_us, std::string_view interface,
                                const hal::CanFrame& frame) {
  char buffer[kMaxCandumpLineChars];
  const std::size_t length = format_candump_line(wall_time_us, interface, frame, buffer);
  return std::string(buffer, length > 0 ? length - 1 : 0);
}

namespace {

// `base`: the column of text[0] in the line, for messages.
hal::CanFrame parse_frame(std::string_view text, std::size_t base) {
  hal::CanFrame frame;
  const std::size_t hash = text.find('#');
  if (hash != 3 && hash != 8) {
    parse_error(base,
                "expected a CAN id of 3 (standard) or 8 (extended) hex digits, then '#', in '" +
                    std::string(text) + "'");
  }
  std::uint32_t id = 0;
  for (std::size_t i = 0; i < hash; ++i) {
    const int digit = hex_value(text[i]);
    if (digit < 0)
      parse_error(base + i,
                  "expected a hex digit in the CAN id, found '" + std::string(1, text[i]) + "'");
    id = (id << 4) | static_cast<std::uint32_t>(digit);
  }
  if (hash == 3) {
    if (id > 0x7FF) parse_error(base, "standard CAN id above 7FF");
    frame.id = id;
  } else if (id & kErrFlag) {
    if (id > (kErrFlag | 0x1FFF'FFFF))
      parse_error(base, "error frame id with flags beyond CAN_ERR_FLAG");
    frame.error_frame = true;
    frame.id = id & 0x1FFF'FFFF;
  } else {
    if (id > 0x1FFF'FFFF) parse_error(base, "extended CAN id above 1FFFFFFF");
    frame.extended_id = true;
    frame.id = id;
  }

  std::size_t at = hash + 1;
  if (at < text.size() && (text[at] == 'R' || text[at] == 'r')) {
    if (frame.error_frame) parse_error(base + at, "an error frame cannot be a remote request");
    frame.remote_request = true;
    ++at;
    if (at < text.size()) {
      const int dlc = hex_value(text[at]);
      if (dlc < 0 || dlc > 8 || at + 1 != text.size()) {
        parse_error(base + at, "expected nothing or a DLC 0-8 after 'R'");
      }
      frame.length = static_cast<std::uint8_t>(dlc);
    }
    return frame;
  }

  std::size_t max_length = hal::CanFrame::kMaxClassicDataBytes;
  if (at < text.size() && text[at] == '#') {
    if (frame.error_frame) parse_error(base + at, "an error frame cannot be a CAN FD frame");
    const int flags = at + 1 < text.size() ? hex_value(text[at + 1]) : -1;
    if (flags < 0) parse_error(base + at + 1, "expected one hex digit of CAN FD flags after '##'");
    frame.fd = true;
    frame.bit_rate_switch = (flags & kFdFlagBrs) != 0;
    frame.error_state_indicator = (flags & kFdFlagEsi) != 0;
    max_length = hal::CanFrame::kMaxFdDataBytes;
    at += 2;
  }
  std::size_t length = 0;
  while (at < text.size()) {
    if (text[at] == '.') {  // lib.c accepts optional separators between bytes
      ++at;
      continue;
    }
    if (length == max_length) {
      parse_error(base + at, "more than " + std::to_string(max_length) + " data bytes");
    }
    const int high = hex_value(text[at]);
    const int low = at + 1 < text.size() ? hex_value(text[at + 1]) : -1;
    if (high < 0 || low < 0) parse_error(base + at, "expected two hex digits per data byte");
    frame.data[length++] = static_cast<std::uint8_t>((high << 4) | low);
    at += 2;
  }
  frame.length = static_cast<std::uint8_t>(length);
  if (frame.fd && !is_can_fd_length(frame.length)) {
    parse_error(base + hash,
                std::to_string(length) +
                    " data bytes is not a CAN FD length (0-8, 12, 16, 20, 24, 32, 48, 64)");
  }
  return frame;
}

}  // namespace

hal::CanFrame parse_candump_frame(std::string_view text) {
  return parse_frame(text, 0);
}

CandumpRecord parse_candump_line(std::string_view line) {
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.remove_suffix(1);
  CandumpRecord record;
  std::size_t at = 0;
  if (line.empty() || line[0] != '(') parse_error(0, "expected '(' starting the timestamp");
  ++at;
  auto digits = [&](std::size_t max_count, const char* what) {
    const std::size_t start = at;
    std::int64_t value = 0;
    while (at < line.size() && line[at] >= '0' && line[at] <= '9') {
      if (at - start == max_count) parse_error(at, std::string("too many digits in ") + what);
      value = value * 10 + (line[at] - '0');
      ++at;
    }
    if (at == start) parse_error(at, std::string("expected the digits of ") + what);
    return std::pair{value, at - start};
  };
  const auto [seconds, seconds_digits] = digits(12, "the timestamp's seconds");
  (void)seconds_digits;
  if (at >= line.size() || line[at] != '.') parse_error(at, "expected '.' in the timestamp");
  ++at;
  const auto [micros, micro_digits] = digits(6, "the timestamp's microseconds");
  if (micro_digits != 6) parse_error(at, "expected 6 digits of microseconds");
  if (at >= line.size() || line[at] != ')') parse_error(at, "expected ')' ending the timestamp");
  ++at;
  record.wall_time_us = seconds * 1'000'000 + micros;

  auto skip_spaces = [&] {
    const std::size_t start = at;
    while (at < line.size() && line[at] == ' ') ++at;
    if (at == start) parse_error(at, "expected a space");
  };
  skip_spaces();  // candump -L pads names to the longest one with spaces
  const std::size_t name_start = at;
  while (at < line.size() && line[at] != ' ') ++at;
  if (at == name_start || at - name_start > kMaxInterfaceChars) {
    parse_error(name_start, "expected an interface name of 1-15 characters");
  }
  record.interface = std::string(line.substr(name_start, at - name_start));
  skip_spaces();
  const std::size_t frame_start = at;
  const std::size_t frame_end = line.find(' ', frame_start);
  if (frame_end != std::string_view::npos) {
    parse_error(frame_end, "unexpected text after the frame");
  }
  record.frame = parse_frame(line.substr(frame_start), frame_start);
  return record;
}

}  // namespace cambio::can
