#pragma once

// CANopen (CiA 301 v4.2) vocabulary shared by the master (drivers/canopen) and the drives the
// virtual rig emulates (sim/virtual_rig): the predefined connection set's COB-IDs, NMT, SDO
// command specifiers and abort codes, object addresses and little-endian field packing.
// Header-only, no allocation: everything here runs on the loop side.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace cambio::canopen {

inline constexpr int kMinNodeId = 1;
inline constexpr int kMaxNodeId = 127;

// Predefined connection set (CiA 301 §7.3.5): function code + node id.
inline constexpr std::uint32_t kNmtCobId = 0x000;
inline constexpr std::uint32_t kSyncCobId = 0x080;
constexpr std::uint32_t emcy_cob_id(int node_id) {
  return 0x080u + static_cast<std::uint32_t>(node_id);
}
/// TPDO n (1..4): drive -> master.
constexpr std::uint32_t tpdo_cob_id(int pdo_number, int node_id) {
  return 0x180u + 0x100u * static_cast<std::uint32_t>(pdo_number - 1) +
         static_cast<std::uint32_t>(node_id);
}
/// RPDO n (1..4): master -> drive.
constexpr std::uint32_t rpdo_cob_id(int pdo_number, int node_id) {
  return 0x200u + 0x100u * static_cast<std::uint32_t>(pdo_number - 1) +
         static_cast<std::uint32_t>(node_id);
}
/// SDO server -> client (the drive's answers).
constexpr std::uint32_t sdo_response_cob_id(int node_id) {
  return 0x580u + static_cast<std::uint32_t>(node_id);
}
/// SDO client -> server (the master's requests).
constexpr std::uint32_t sdo_request_cob_id(int node_id) {
  return 0x600u + static_cast<std::uint32_t>(node_id);
}
/// NMT error control: heartbeat and boot-up.
constexpr std::uint32_t heartbeat_cob_id(int node_id) {
  return 0x700u + static_cast<std::uint32_t>(node_id);
}

/// The node id a frame of the predefined connection set comes from (0 for NMT and SYNC).
constexpr int node_of(std::uint32_t cob_id) {
  return static_cast<int>(cob_id & 0x7Fu);
}
/// The function code (cob_id without the node id).
constexpr std::uint32_t function_of(std::uint32_t cob_id) {
  return cob_id & 0x780u;
}

/// Bit 31 of a PDO's COB-ID entry (0x1400/0x1800 sub 1): the PDO does not exist (invalid).
inline constexpr std::uint32_t kPdoCobIdInvalid = 0x8000'0000u;
/// Bit 30 of a TPDO's COB-ID entry: no RTR allowed.
inline constexpr std::uint32_t kPdoCobIdNoRtr = 0x4000'0000u;
/// Transmission type 1 (0x1400/0x1800 sub 2): synchronous, every SYNC.
inline constexpr std::uint8_t kTransmissionSyncEvery = 1;

// NMT module control (CiA 301 §7.2.8.3.1): frame [command, node id]; node id 0 = all nodes.
enum class NmtCommand : std::uint8_t {
  kStart = 0x01,
  kStop = 0x02,
  kEnterPreOperational = 0x80,
  kResetNode = 0x81,
  kResetCommunication = 0x82,
};

/// NMT state as carried by a heartbeat (byte 0, bit 7 is the toggle bit of node guarding).
enum class NmtState : std::uint8_t {
  kBootUp = 0x00,
  kStopped = 0x04,
  kOperational = 0x05,
  kPreOperational = 0x7F,
};

constexpr std::string_view to_string(NmtState state) {
  switch (state) {
    case NmtState::kBootUp:
      return "boot-up";
    case NmtState::kStopped:
      return "stopped";
    case NmtState::kOperational:
      return "operational";
    case NmtState::kPreOperational:
      return "pre-operational";
  }
  return "unknown";
}

// SDO command specifiers (CiA 301 §7.2.4.3), the top 3 bits of byte 0.
inline constexpr std::uint8_t kSdoClientDownloadSegment = 0;   ///< ccs 0
inline constexpr std::uint8_t kSdoClientInitiateDownload = 1;  ///< ccs 1
inline constexpr std::uint8_t kSdoClientInitiateUpload = 2;    ///< ccs 2
inline constexpr std::uint8_t kSdoClientUploadSegment = 3;     ///< ccs 3
inline constexpr std::uint8_t kSdoServerUploadSegment = 0;     ///< scs 0
inline constexpr std::uint8_t kSdoServerDownloadSegment = 1;   ///< scs 1
inline constexpr std::uint8_t kSdoServerInitiateUpload = 2;    ///< scs 2
inline constexpr std::uint8_t kSdoServerInitiateDownload = 3;  ///< scs 3
inline constexpr std::uint8_t kSdoAbort = 4;                   ///< cs 4, either direction.

constexpr std::uint8_t sdo_command_specifier(std::uint8_t byte0) {
  return byte0 >> 5;
}

/// SDO abort codes (CiA 301 Table 22) the stack sends or reports by name.
enum class SdoAbortCode : std::uint32_t {
  kToggleBitNotAlternated = 0x0503'0000,
  kTimeout = 0x0504'0000,
  kInvalidCommandSpecifier = 0x0504'0001,
  kOutOfMemory = 0x0504'0005,
  kUnsupportedAccess = 0x0601'0000,
  kWriteOnly = 0x0601'0001,
  kReadOnly = 0x0601'0002,
  kObjectDoesNotExist = 0x0602'0000,
  kCannotMapToPdo = 0x0604'0041,
  kPdoLengthExceeded = 0x0604'0042,
  kGeneralParameterIncompatibility = 0x0604'0043,
  kHardwareError = 0x0606'0000,
  kLengthMismatch = 0x0607'0010,
  kLengthTooHigh = 0x0607'0012,
  kLengthTooLow = 0x0607'0013,
  kSubindexDoesNotExist = 0x0609'0011,
  kInvalidValue = 0x0609'0030,
  kValueTooHigh = 0x0609'0031,
  kValueTooLow = 0x0609'0032,
  kGeneralError = 0x0800'0000,
  kCannotStoreOrTransfer = 0x0800'0020,
  kCannotTransferLocalControl = 0x0800'0021,
  kCannotTransferDeviceState = 0x0800'0022,
};

/// The abort code's meaning as CiA 301 words it ("" for a code the standard does not list).
constexpr std::string_view sdo_abort_name(std::uint32_t code) {
  switch (static_cast<SdoAbortCode>(code)) {
    case SdoAbortCode::kToggleBitNotAlternated:
      return "toggle bit not alternated";
    case SdoAbortCode::kTimeout:
      return "SDO protocol timed out";
    case SdoAbortCode::kInvalidCommandSpecifier:
      return "client/server command specifier not valid or unknown";
    case SdoAbortCode::kOutOfMemory:
      return "out of memory";
    case SdoAbortCode::kUnsupportedAccess:
      return "unsupported access to an object";
    case SdoAbortCode::kWriteOnly:
      return "attempt to read a write only object";
    case SdoAbortCode::kReadOnly:
      return "attempt to write a read only object";
    case SdoAbortCode::kObjectDoesNotExist:
      return "object does not exist in the object dictionary";
    case SdoAbortCode::kCannotMapToPdo:
      return "object cannot be mapped to the PDO";
    case SdoAbortCode::kPdoLengthExceeded:
      return "the number and length of the objects to be mapped would exceed PDO length";
    case SdoAbortCode::kGeneralParameterIncompatibility:
      return "general parameter incompatibility reason";
    case SdoAbortCode::kHardwareError:
      return "access failed due to a hardware error";
    case SdoAbortCode::kLengthMismatch:
      return "data type does not match, length of service parameter does not match";
    case SdoAbortCode::kLengthTooHigh:
      return "data type does not match, length of service parameter too high";
    case SdoAbortCode::kLengthTooLow:
      return "data type does not match, length of service parameter too low";
    case SdoAbortCode::kSubindexDoesNotExist:
      return "sub-index does not exist";
    case SdoAbortCode::kInvalidValue:
      return "invalid value for parameter";
    case SdoAbortCode::kValueTooHigh:
      return "value of parameter written too high";
    case SdoAbortCode::kValueTooLow:
      return "value of parameter written too low";
    case SdoAbortCode::kGeneralError:
      return "general error";
    case SdoAbortCode::kCannotStoreOrTransfer:
      return "data cannot be transferred or stored to the application";
    case SdoAbortCode::kCannotTransferLocalControl:
      return "data cannot be transferred or stored to the application because of local control";
    case SdoAbortCode::kCannotTransferDeviceState:
      return "data cannot be transferred or stored to the application because of the present "
             "device state";
  }
  return "";
}

/// An entry of an object dictionary.
struct ObjectAddress {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  friend constexpr bool operator==(ObjectAddress, ObjectAddress) = default;
};

// Communication profile objects (CiA 301 §7.5.2) the stack uses.
inline constexpr std::uint16_t kDeviceType = 0x1000;
inline constexpr std::uint16_t kErrorRegister = 0x1001;
inline constexpr std::uint16_t kCobIdSync = 0x1005;
inline constexpr std::uint16_t kCommunicationCyclePeriod = 0x1006;
inline constexpr std::uint16_t kManufacturerDeviceName = 0x1008;
inline constexpr std::uint16_t kCobIdEmcy = 0x1014;
inline constexpr std::uint16_t kConsumerHeartbeatTime = 0x1016;
inline constexpr std::uint16_t kProducerHeartbeatTime = 0x1017;
inline constexpr std::uint16_t kIdentity = 0x1018;
inline constexpr std::uint16_t kRpdoCommunication = 0x1400;  ///< + n-1 for RPDO n.
inline constexpr std::uint16_t kRpdoMapping = 0x1600;
inline constexpr std::uint16_t kTpdoCommunication = 0x1800;
inline constexpr std::uint16_t kTpdoMapping = 0x1A00;

/// A PDO mapping entry (0x1600/0x1A00 sub 1..8): index << 16 | subindex << 8 | length in bits.
constexpr std::uint32_t pdo_mapping_entry(ObjectAddress object, int bits) {
  return static_cast<std::uint32_t>(object.index) << 16 |
         static_cast<std::uint32_t>(object.subindex) << 8 | static_cast<std::uint32_t>(bits);
}
constexpr ObjectAddress mapped_object(std::uint32_t entry) {
  return {static_cast<std::uint16_t>(entry >> 16), static_cast<std::uint8_t>(entry >> 8)};
}
constexpr int mapped_bits(std::uint32_t entry) {
  return static_cast<int>(entry & 0xFFu);
}

/// Little-endian unsigned field of `bytes` (1..4) at `offset`. The caller checks the bounds.
constexpr std::uint32_t get_le(std::span<const std::uint8_t> data, std::size_t offset,
                               std::size_t bytes) {
  std::uint32_t value = 0;
  for (std::size_t i = 0; i < bytes; ++i) {
    value |= static_cast<std::uint32_t>(data[offset + i]) << (8 * i);
  }
  return value;
}
constexpr void put_le(std::span<std::uint8_t> data, std::size_t offset, std::size_t bytes,
                      std::uint32_t value) {
  for (std::size_t i = 0; i < bytes; ++i) {
    data[offset + i] = static_cast<std::uint8_t>(value >> (8 * i));
  }
}
/// Sign-extends the low `bytes` bytes of `value`.
constexpr std::int32_t sign_extend(std::uint32_t value, std::size_t bytes) {
  if (bytes >= 4) return static_cast<std::int32_t>(value);
  const std::uint32_t sign = 1u << (8 * bytes - 1);
  const std::uint32_t mask = (1u << (8 * bytes)) - 1u;
  value &= mask;
  return static_cast<std::int32_t>((value ^ sign) - sign);
}

/// EMCY frame (CiA 301 §7.2.7.3.1): error code (2 bytes), error register (1), vendor (5).
struct Emergency {
  std::uint16_t error_code = 0;  ///< 0x0000 = error reset / no error.
  std::uint8_t error_register = 0;
};

}  // namespace cambio::canopen
