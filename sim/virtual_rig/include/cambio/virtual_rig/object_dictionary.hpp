#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/canopen/protocol.hpp"

namespace cambio::virtual_rig {

/// CANopen basic data types (CiA 301 Table 44), with their object dictionary index (the number an
/// EDS's DataType field holds).
enum class DataType : std::uint16_t {
  kBoolean = 0x0001,
  kInteger8 = 0x0002,
  kInteger16 = 0x0003,
  kInteger32 = 0x0004,
  kUnsigned8 = 0x0005,
  kUnsigned16 = 0x0006,
  kUnsigned32 = 0x0007,
  kVisibleString = 0x0009,
};

/// Bytes a value of a numeric type takes (0 for a string: its length is the value's).
constexpr std::size_t size_of(DataType type) {
  switch (type) {
    case DataType::kBoolean:
    case DataType::kInteger8:
    case DataType::kUnsigned8:
      return 1;
    case DataType::kInteger16:
    case DataType::kUnsigned16:
      return 2;
    case DataType::kInteger32:
    case DataType::kUnsigned32:
      return 4;
    case DataType::kVisibleString:
      return 0;
  }
  return 0;
}

constexpr bool is_signed(DataType type) {
  return type == DataType::kInteger8 || type == DataType::kInteger16 ||
         type == DataType::kInteger32;
}

/// Access of an entry as an EDS's AccessType says it (CiA 306 §4.6.3).
enum class Access : std::uint8_t {
  kReadOnly,   ///< "ro": the device may change it (actual values).
  kReadWrite,  ///< "rw".
  kWriteOnly,  ///< "wo".
  kConst,      ///< "const": never changes.
};

constexpr bool readable(Access access) {
  return access != Access::kWriteOnly;
}
constexpr bool writable(Access access) {
  return access == Access::kReadWrite || access == Access::kWriteOnly;
}

/// One entry (index:subindex) of an object dictionary. Numeric values are held as their raw
/// little-endian bits in `value` (sign-extended on reading for the INTEGER types); a
/// VISIBLE_STRING's text is fixed at construction (the emulated drive has no writable strings).
struct ObjectEntry {
  canopen::ObjectAddress address;
  std::string_view name;  ///< As the EDS's ParameterName.
  DataType type = DataType::kUnsigned32;
  Access access = Access::kReadOnly;
  bool pdo_mappable = false;
  std::int64_t low = 0;   ///< Valid range of a numeric value (inclusive), checked on writes.
  std::int64_t high = 0;  ///< Set from the type when low == high == 0.
  std::uint32_t value = 0;
  std::uint32_t default_value = 0;
  std::string text;  ///< VISIBLE_STRING only.

  /// Bytes the entry's value takes on the bus.
  std::size_t size() const {
    return type == DataType::kVisibleString ? text.size() : size_of(type);
  }
  std::int64_t as_integer() const {
    return is_signed(type) ? canopen::sign_extend(value, size_of(type))
                           : static_cast<std::int64_t>(value);
  }
};

/// A CANopen object dictionary (CiA 301 §7.4): entries by index:subindex with data type, access,
/// PDO mappability, valid range and value. All entries are added before use (construction);
/// reads and writes never allocate afterwards and are real-time safe. Not thread-safe.
class ObjectDictionary {
 public:
  /// Adds a numeric entry; the range defaults to the type's. Throws std::logic_error on a
  /// duplicate address (a programming error). Not for use after finalise().
  ObjectEntry& add(canopen::ObjectAddress address, std::string_view name, DataType type,
                   Access access, std::uint32_t default_value, bool pdo_mappable = false);
  /// Adds a VISIBLE_STRING entry (const).
  ObjectEntry& add_string(canopen::ObjectAddress address, std::string_view name, std::string text);
  /// Sorts the entries for lookup; entries keep their addresses from here on (pointers into the
  /// dictionary stay valid for its lifetime).
  void finalise();

  /// The entry at `address`, or nullptr.
  ObjectEntry* find(canopen::ObjectAddress address) noexcept;
  const ObjectEntry* find(canopen::ObjectAddress address) const noexcept;
  /// True when any entry has this index.
  bool has_index(std::uint16_t index) const noexcept;
  /// The abort code for an address that has no entry: object or subindex does not exist
  /// (0 when it exists).
  std::uint32_t missing_code(canopen::ObjectAddress address) const noexcept;

  /// Reads an entry's value as the bus carries it (little-endian, strings without terminator)
  /// into `out`; `size` is set to the byte count. Returns 0 or an SDO abort code (object or
  /// subindex does not exist, write only, out of memory when `out` is too small).
  std::uint32_t read(canopen::ObjectAddress address, std::span<std::uint8_t> out,
                     std::size_t& size) const noexcept;
  /// Validates a write from the bus (existence, access, length, range) and stores it. Returns 0
  /// or the SDO abort code. Side effects (what the device does with the value) are the caller's.
  std::uint32_t write(canopen::ObjectAddress address, std::span<const std::uint8_t> data) noexcept;
  /// The validation of write() without storing.
  std::uint32_t check_write(canopen::ObjectAddress address,
                            std::span<const std::uint8_t> data) const noexcept;

  /// Device-side access: sets a value whatever its access (actual values, statusword).
  void set(canopen::ObjectAddress address, std::uint32_t value) noexcept;
  std::uint32_t get(canopen::ObjectAddress address) const noexcept;
  std::int32_t get_signed(canopen::ObjectAddress address) const noexcept;

  /// Restores default values of the entries with index in [first, last] (NMT resets).
  void restore_defaults(std::uint16_t first, std::uint16_t last) noexcept;

  std::span<const ObjectEntry> entries() const { return entries_; }

 private:
  std::vector<ObjectEntry> entries_;
  bool finalised_ = false;
};

}  // namespace cambio::virtual_rig
