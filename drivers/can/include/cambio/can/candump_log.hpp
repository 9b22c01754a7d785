#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "cambio/hal/can_bus.hpp"

namespace cambio::can {

/// One line of can-utils' log format (`candump -L`, `candump -l`, read by `canplayer`), as
/// can-utils' lib.c prints it:
///
///     (1436509052.249713) vcan0 123#DEADBEEF
///
/// `(seconds.microseconds)` of wall-clock time (CLOCK_REALTIME), the interface, then the frame:
/// - `123#DEADBEEF`: standard id (3 hex digits), data in upper-case hex, no separators;
/// - `12345678#112233`: extended id (8 hex digits, without CAN_EFF_FLAG);
/// - `123#R`, `123#R3`: remote request (classic), with its DLC when it is not 0;
/// - `123##5112233`: CAN FD: `##`, one hex digit of canfd_frame.flags (CANFD_BRS 1, CANFD_ESI 2,
///   CANFD_FDF 4, which Linux >= 6.0 sets on every FD frame and we print always, so our lines
///   match candump's), then the data;
/// - `20000004#0004000000000000`: an error frame: 8 hex digits of CAN_ERR_FLAG | class bits.
struct CandumpRecord {
  std::int64_t wall_time_us = 0;  ///< Microseconds since the Unix epoch.
  std::string interface;
  hal::CanFrame frame;  ///< stamp_ns left 0.
};

/// A line that is not a candump -L record; what() says where and what was expected.
class CandumpParseError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Longest formatted frame: 8-digit id, `##`, the flags digit, 64 data bytes.
inline constexpr std::size_t kMaxCandumpFrameChars = 8 + 2 + 1 + 2 * 64;
/// Longest line, with its '\n': timestamp (up to 20 + 1 + 6 digits, parentheses), interface
/// (15 characters), separators.
inline constexpr std::size_t kMaxCandumpLineChars = 30 + 1 + 15 + 1 + kMaxCandumpFrameChars + 1;

/// Writes the frame text (`123#DEADBEEF`) into `out` (at least kMaxCandumpFrameChars long) and
/// returns its length. No allocation.
std::size_t format_candump_frame(const hal::CanFrame& frame, std::span<char> out) noexcept;
std::string format_candump_frame(const hal::CanFrame& frame);

/// Writes the whole line, with a final '\n', into `out` (at least kMaxCandumpLineChars long)
/// and returns its length; an interface name is cut at 15 characters (IFNAMSIZ). No allocation.
std::size_t format_candump_line(std::int64_t wall_time_us, std::string_view interface,
                                const hal::CanFrame& frame, std::span<char> out) noexcept;
/// The line without its '\n'.
std::string format_candump_line(std::int64_t wall_time_us, std::string_view interface,
                                const hal::CanFrame& frame);

/// Parses the frame text. Throws CandumpParseError (column and expectation) on anything lib.c
/// would not print: bad hex, an id of other than 3 or 8 digits or out of range, more data than
/// the frame type holds, an FD length that is not a CAN FD length.
hal::CanFrame parse_candump_frame(std::string_view text);
/// Parses one line (a trailing '\n' or "\r\n" is accepted). Throws CandumpParseError.
CandumpRecord parse_candump_line(std::string_view line);

}  // namespace cambio::can
