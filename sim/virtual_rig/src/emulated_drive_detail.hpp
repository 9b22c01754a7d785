#pragma once

// What the emulated drive's source files share (emulated_drive.cpp: NMT, SDO target, CiA 402
// state machine, faults; emulated_drive_dictionary.cpp: the object dictionary;
// emulated_drive_pdo.cpp: PDO mapping and transfer). Not installed.

#include <cmath>
#include <cstdint>

#include "cambio/virtual_rig/emulated_drive.hpp"

namespace cambio::virtual_rig::emulated_drive_detail {

using canopen::NmtState;
using canopen::ObjectAddress;
using canopen::SdoAbortCode;
using hal::DriveState;
namespace cia402 = canopen::cia402;

inline constexpr std::uint32_t code(SdoAbortCode abort) {
  return static_cast<std::uint32_t>(abort);
}

inline constexpr std::int64_t kNsPerS = 1'000'000'000;
/// After a longer silence the servo skips ahead instead of replaying it step by step.
inline constexpr std::int64_t kMaxCatchUpNs = kNsPerS;

// Error register (0x1001) bits, CiA 301 Table 48.
inline constexpr std::uint8_t kErrorGeneric = 1u << 0;
inline constexpr std::uint8_t kErrorCommunication = 1u << 4;

// EMCY error codes (CiA 301 Table 21, CiA 402-2 Table 2).
inline constexpr std::uint16_t kEmcyErrorReset = 0x0000;
inline constexpr std::uint16_t kEmcyCanErrorPassive = 0x8120;
inline constexpr std::uint16_t kEmcyPdoLength = 0x8210;
inline constexpr std::uint16_t kEmcyFollowingError = 0x8611;

inline constexpr std::uint32_t kFollowingErrorOff = 0xFFFF'FFFF;

/// Supported drive modes (0x6502): bit 5 homing, bit 7 cyclic synchronous position, bit 8
/// cyclic synchronous velocity.
inline constexpr std::uint32_t kSupportedModes = (1u << 5) | (1u << 7) | (1u << 8);

inline bool in(std::uint16_t index, std::uint16_t first) {
  return index >= first && index < first + EmulatedDrive::kPdoCount;
}

inline std::uint32_t saturating_counts(double counts) {
  if (!(counts < 4294967295.0)) return 0xFFFF'FFFFu;
  return counts > 0.0 ? static_cast<std::uint32_t>(std::lround(counts)) : 0u;
}

}  // namespace cambio::virtual_rig::emulated_drive_detail
