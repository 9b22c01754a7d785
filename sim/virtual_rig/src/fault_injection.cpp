#include "cambio/virtual_rig/fault_injection.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "cambio/config/echoed_text.hpp"

namespace cambio::virtual_rig {

namespace {

constexpr std::array<std::pair<FaultKind, std::string_view>, 7> kKinds = {{
    {FaultKind::kHeartbeatStop, "heartbeat-stop"},
    {FaultKind::kEmergency, "emcy"},
    {FaultKind::kFollowingError, "following-error"},
    {FaultKind::kErrorFrames, "error-frames"},
    {FaultKind::kDropTpdo, "drop-tpdo"},
    {FaultKind::kLateTpdo, "late-tpdo"},
    {FaultKind::kSdoAbort, "sdo-abort"},
}};

// Every piece of the spec a message repeats goes through config::echoed: control characters
// (a NUL would cut the message, an escape sequence act on the terminal) escaped, long text cut.
std::string echo(std::string_view text) {
  return config::echoed(text);
}

[[noreturn]] void fail(std::string_view spec, const std::string& why) {
  throw std::invalid_argument("fault '" + echo(spec) + "': " + why);
}

/// A whole number, decimal or 0x-hex, within [low, high].
std::int64_t whole(std::string_view spec, std::string_view key, std::string_view text,
                   std::int64_t low, std::int64_t high) {
  int base = 10;
  std::string_view digits = text;
  if (digits.size() > 2 && digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X')) {
    base = 16;
    digits.remove_prefix(2);
  }
  std::int64_t value = 0;
  const auto [end, error] =
      std::from_chars(digits.data(), digits.data() + digits.size(), value, base);
  if (digits.empty() || error != std::errc() || end != digits.data() + digits.size()) {
    fail(spec, std::string(key) + ": expected a whole number, found '" + echo(text) + "'");
  }
  if (value < low || value > high) {
    fail(spec, std::string(key) + ": expected " + std::to_string(low) + " to " +
                   std::to_string(high) + ", found " + echo(text));
  }
  return value;
}

double real(std::string_view spec, std::string_view key, std::string_view text, double low,
            double high) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() ||
      !std::isfinite(value)) {
    fail(spec, std::string(key) + ": expected a number, found '" + echo(text) + "'");
  }
  if (value < low || value > high) {
    fail(spec, std::string(key) + ": expected " + std::to_string(low) + " to " +
                   std::to_string(high) + ", found " + echo(text));
  }
  return value;
}

}  // namespace

std::string_view to_string(FaultKind kind) {
  for (const auto& [k, name] : kKinds) {
    if (k == kind) return name;
  }
  return "unknown";
}

FaultInjection parse_fault(std::string_view spec) {
  FaultInjection fault;
  std::string_view rest = spec;
  const auto next_field = [&rest]() {
    const std::size_t comma = rest.find(',');
    const std::string_view field = rest.substr(0, comma);
    rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    return field;
  };
  const std::string_view kind = next_field();
  bool known = false;
  for (const auto& [k, name] : kKinds) {
    if (name == kind) {
      fault.kind = k;
      known = true;
    }
  }
  if (!known) {
    std::string names;
    for (const auto& [k, name] : kKinds) names += (names.empty() ? "" : ", ") + std::string(name);
    fail(spec, "unknown kind '" + echo(kind) + "'; expected one of " + names);
  }
  if (fault.kind == FaultKind::kErrorFrames) fault.count = 10;
  bool has_object = false;
  std::vector<std::string_view> keys_seen;
  while (!rest.empty()) {
    const std::string_view field = next_field();
    const std::size_t equals = field.find('=');
    if (equals == std::string_view::npos) {
      fail(spec, "expected key=value, found '" + echo(field) + "'");
    }
    const std::string_view key = field.substr(0, equals);
    const std::string_view value = field.substr(equals + 1);
    // One value per key, and one time: a second would silently win over the first.
    const std::string_view slot = key == "after_enable_s" ? std::string_view("at_s") : key;
    for (const std::string_view& earlier : keys_seen) {
      if (earlier != slot) continue;
      fail(spec, slot == "at_s" ? std::string("give one time, at_s or after_enable_s, once")
                                : "key '" + echo(key) + "' given twice");
    }
    keys_seen.push_back(slot);
    if (key == "node") {
      fault.node_id =
          static_cast<int>(whole(spec, key, value, canopen::kMinNodeId, canopen::kMaxNodeId));
    } else if (key == "at_s") {
      fault.at_s = real(spec, key, value, 0.0, 1e6);
      fault.after_enable = false;
    } else if (key == "after_enable_s") {
      fault.at_s = real(spec, key, value, 0.0, 1e6);
      fault.after_enable = true;
    } else if (key == "code" && fault.kind == FaultKind::kSdoAbort) {
      fault.abort_code = static_cast<std::uint32_t>(whole(spec, key, value, 1, 0xFFFF'FFFF));
    } else if (key == "code" && fault.kind == FaultKind::kEmergency) {
      fault.emcy_code = static_cast<std::uint16_t>(whole(spec, key, value, 1, 0xFFFF));
    } else if (key == "fault" && fault.kind == FaultKind::kEmergency) {
      if (value != "yes" && value != "no") {
        fail(spec, "fault: expected yes or no, found '" + echo(value) + "'");
      }
      fault.latch_fault = value == "yes";
    } else if (key == "count" &&
               (fault.kind == FaultKind::kDropTpdo || fault.kind == FaultKind::kLateTpdo ||
                fault.kind == FaultKind::kErrorFrames)) {
      fault.count = static_cast<int>(whole(spec, key, value, 1, 1'000'000));
    } else if (key == "delay_ms" && fault.kind == FaultKind::kLateTpdo) {
      fault.delay_s = real(spec, key, value, 0.0, 10'000.0) / 1000.0;
    } else if (key == "object" && fault.kind == FaultKind::kSdoAbort) {
      const std::size_t colon = value.find(':');
      if (colon == std::string_view::npos) {
        fail(spec, "object: expected INDEX:SUB, e.g. 0x6065:0, found '" + echo(value) + "'");
      }
      fault.object.index = static_cast<std::uint16_t>(
          whole(spec, "object index", value.substr(0, colon), 0, 0xFFFF));
      fault.object.subindex = static_cast<std::uint8_t>(
          whole(spec, "object subindex", value.substr(colon + 1), 0, 0xFF));
      has_object = true;
    } else {
      fail(spec, "key '" + echo(key) + "' does not apply to " + std::string(kind) +
                     " (keys: node, at_s, after_enable_s" +
                     (fault.kind == FaultKind::kEmergency ? ", code, fault" : "") +
                     (fault.kind == FaultKind::kSdoAbort ? ", object, code" : "") +
                     (fault.kind == FaultKind::kLateTpdo ? ", count, delay_ms" : "") +
                     (fault.kind == FaultKind::kDropTpdo || fault.kind == FaultKind::kErrorFrames
                          ? ", count"
                          : "") +
                     ")");
    }
  }
  if (fault.kind == FaultKind::kSdoAbort && !has_object) {
    fail(spec, "sdo-abort needs object=INDEX:SUB");
  }
  return fault;
}

std::string describe(const FaultInjection& fault) {
  char text[160];
  const std::string node =
      fault.node_id == 0 ? std::string("every drive") : "node " + std::to_string(fault.node_id);
  switch (fault.kind) {
    case FaultKind::kHeartbeatStop:
      std::snprintf(text, sizeof text, "heartbeat stops");
      break;
    case FaultKind::kEmergency:
      std::snprintf(text, sizeof text, "EMCY 0x%04X%s", fault.emcy_code,
                    fault.latch_fault ? " and fault" : " (no fault)");
      break;
    case FaultKind::kFollowingError:
      std::snprintf(text, sizeof text, "following error fault (EMCY 0x8611)");
      break;
    case FaultKind::kErrorFrames:
      std::snprintf(text, sizeof text,
                    "bus error burst reported as EMCY 0x8120 for %d SYNC periods", fault.count);
      break;
    case FaultKind::kDropTpdo:
      std::snprintf(text, sizeof text, "%d TPDOs dropped", fault.count);
      break;
    case FaultKind::kLateTpdo:
      std::snprintf(text, sizeof text, "%d TPDOs sent %.1f ms late", fault.count,
                    fault.delay_s * 1000.0);
      break;
    case FaultKind::kSdoAbort:
      std::snprintf(text, sizeof text, "SDO access to 0x%04X:%u aborted with 0x%08X",
                    fault.object.index, fault.object.subindex, fault.abort_code);
      break;
  }
  char when[48];
  std::snprintf(when, sizeof when, fault.after_enable ? " %.3f s after enable" : " at %.3f s",
                fault.at_s);
  return node + ": " + text + when;
}

}  // namespace cambio::virtual_rig
