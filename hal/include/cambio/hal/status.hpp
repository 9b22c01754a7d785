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

/// How bad a status is, for merging the results of several devices: a loop reports the worst,
/// never the last one seen. kOk < kNoNewData < kStale < kRejected < kFault.
constexpr int severity(Status status) {
  switch (status) {
    case Status::kOk:
      return 0;
    case Status::kNoNewData:
      return 1;
    case Status::kStale:
      return 2;
    case Status::kRejected:
      return 3;
    case Status::kFault:
      return 4;
  }
  return 4;
}

/// The more severe of two statuses.
constexpr Status worst(Status a, Status b) {
  return severity(b) > severity(a) ? b : a;
}

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
