#pragma once

// The vocabulary of an EDS object's keys: DataType codes (CiA 301 Table 44, 0x0001..0x001B),
// AccessType (CiA 306 §4.6.3) and ObjectType (CiA 301 Table 42).

#include <cstdint>
#include <optional>
#include <string_view>

namespace cambio::canopen::eds {

struct DataTypeInfo {
  enum class Kind : std::uint8_t { kBoolean, kSigned, kUnsigned, kReal, kString, kTime, kDomain };
  std::uint16_t code = 0;
  std::string_view name;  ///< As CiA 301 spells it, e.g. "UNSIGNED32".
  int bits = 0;           ///< Size on the bus; 0 for variable length (strings, DOMAIN).
  Kind kind = Kind::kDomain;

  /// An integer (or BOOLEAN) whose DefaultValue and limits are numbers.
  bool is_integer() const {
    return kind == Kind::kBoolean || kind == Kind::kSigned || kind == Kind::kUnsigned;
  }
};

/// The standard data type with `code`, or nullptr (reserved 0x000E, 0x0017 and anything beyond
/// 0x001B are not data types a variable can have).
const DataTypeInfo* find_data_type(std::uint16_t code);

/// CiA 306 §4.6.3. rwr and rww are read-write over SDO; the suffix says which PDO direction
/// (process input / output) a tool should map them in.
enum class AccessType : std::uint8_t { kRo, kWo, kRw, kRwr, kRww, kConst };

/// ro, wo, rw, rwr, rww, const in any case; nullopt otherwise.
std::optional<AccessType> parse_access_type(std::string_view text);
std::string_view to_string(AccessType access);
constexpr bool readable(AccessType access) {
  return access != AccessType::kWo;
}
constexpr bool writable(AccessType access) {
  return access == AccessType::kWo || access == AccessType::kRw || access == AccessType::kRwr ||
         access == AccessType::kRww;
}

/// CiA 301 Table 42.
enum class ObjectType : std::uint8_t {
  kNull = 0x0,
  kDomain = 0x2,
  kDefType = 0x5,
  kDefStruct = 0x6,
  kVar = 0x7,
  kArray = 0x8,
  kRecord = 0x9,
};

/// The object type with `code`, or nullopt.
std::optional<ObjectType> object_type_of(std::uint64_t code);
std::string_view to_string(ObjectType type);
/// ARRAY, RECORD and DEFSTRUCT hold sub-indices in sections of their own; the others are one value.
constexpr bool has_sub_sections(ObjectType type) {
  return type == ObjectType::kArray || type == ObjectType::kRecord ||
         type == ObjectType::kDefStruct;
}

}  // namespace cambio::canopen::eds
