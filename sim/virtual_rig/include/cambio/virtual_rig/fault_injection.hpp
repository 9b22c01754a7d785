#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "cambio/canopen/protocol.hpp"

namespace cambio::virtual_rig {

/// What an injected fault does to an emulated drive.
enum class FaultKind : std::uint8_t {
  kHeartbeatStop,   ///< The drive stops producing its heartbeat (a dead node, seen by the master).
  kEmergency,       ///< An EMCY with a given error code; latches a drive fault unless fault=no.
  kFollowingError,  ///< Following error (EMCY 0x8611, statusword bit 13, drive fault).
  /// A burst of bus errors. User space cannot put error frames on a bus (vcan carries none; a
  /// real controller makes them from bit errors), so the drive reports what a real one reports
  /// after such a burst: EMCY 0x8120 "CAN in error passive mode" (error register bit 4), then,
  /// `count` SYNC periods later, EMCY 0x0000 when it is back to error active. The master's own
  /// error-frame path is tested with the kernel's error frames on a real interface, not here.
  kErrorFrames,
  kDropTpdo,  ///< The next `count` TPDO transmissions are not sent.
  kLateTpdo,  ///< The next `count` TPDO transmissions go out `delay_s` after their SYNC.
  kSdoAbort,  ///< Every SDO access to `object` is answered with `abort_code`.
};

/// One fault to inject into the drive(s) at `at_s` seconds after the rig started, or, with
/// `after_enable`, `at_s` seconds after the drive first reached operation enabled (a master's
/// start-up time is unknown to the rig; this places a fault while the master drives it).
struct FaultInjection {
  FaultKind kind = FaultKind::kEmergency;
  int node_id = 0;  ///< 0 = every drive.
  double at_s = 0.0;
  bool after_enable = false;
  std::uint16_t emcy_code = 0x1000;  ///< kEmergency: the error code (default "generic error").
  bool latch_fault = true;           ///< kEmergency: the drive also enters fault.
  int count = 1;                     ///< kDropTpdo / kLateTpdo / kErrorFrames.
  double delay_s = 0.002;            ///< kLateTpdo.
  canopen::ObjectAddress object{};   ///< kSdoAbort.
  std::uint32_t abort_code = 0x0606'0000;  ///< kSdoAbort (default: hardware error).
};

/// Parses a fault specification, `KIND[,key=value]...`, where KIND is one of heartbeat-stop,
/// emcy, following-error, error-frames, drop-tpdo, late-tpdo, sdo-abort, and the keys are
/// node (1..127, default every drive), at_s (>= 0) or after_enable_s (>= 0), code (EMCY code,
/// 0x0001..0xFFFF; SDO abort code), fault (yes/no), count (1..1000000), delay_ms (0..10000), object
/// (INDEX:SUB in hex, e.g. 0x6065:0). Examples: `emcy,node=1,at_s=2,code=0x7300`,
/// `late-tpdo,count=50,delay_ms=3`. Throws std::invalid_argument naming the key and what was
/// expected.
FaultInjection parse_fault(std::string_view spec);

/// The kinds' names as parse_fault() takes them.
std::string_view to_string(FaultKind kind);

/// One line saying what the fault does and when, for logs.
std::string describe(const FaultInjection& fault);

}  // namespace cambio::virtual_rig
