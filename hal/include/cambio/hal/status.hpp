#pragma once

#include <cstdint>
#include <string_view>

namespace cambio::hal {

/// Result of a call made inside a loop. Loops never throw; they return one of these.
enum class [[nodiscard]] Status : std::uint8_t{
    kOk,
    kNoNewData,  ///< Nothing new since the last call; the output was left untouched.
    kStale,      ///< The newest data is older than the caller's freshness bound.
    kRejected,   ///< The input was refused (wrong size, not configured, out of range).
    kFault,      ///< The device reports a fault; see its status bits.
};

constexpr std::string_view to_string(Status status) {
  switch (status) {
    case Status::kOk:
      return "ok";
    case Status::kNoNewData:
      return "no-new-data";
    case Status::kStale:
      return "stale";
    case Status::kRejected:
      return "rejected";
    case Status::kFault:
      return "fault";
  }
  return "unknown";
}

}  // namespace cambio::hal
