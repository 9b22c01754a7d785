#include "cambio/canopen/eds/eds_data_type.hpp"

#include <array>
#include <cctype>

namespace cambio::canopen::eds {

namespace {

using Kind = DataTypeInfo::Kind;

// CiA 301 Table 44 (static data types); 0x000E and 0x0017 are reserved.
constexpr std::array kDataTypes = {
    DataTypeInfo{0x0001, "BOOLEAN", 1, Kind::kBoolean},
    DataTypeInfo{0x0002, "INTEGER8", 8, Kind::kSigned},
    DataTypeInfo{0x0003, "INTEGER16", 16, Kind::kSigned},
    DataTypeInfo{0x0004, "INTEGER32", 32, Kind::kSigned},
    DataTypeInfo{0x0005, "UNSIGNED8", 8, Kind::kUnsigned},
    DataTypeInfo{0x0006, "UNSIGNED16", 16, Kind::kUnsigned},
    DataTypeInfo{0x0007, "UNSIGNED32", 32, Kind::kUnsigned},
    DataTypeInfo{0x0008, "REAL32", 32, Kind::kReal},
    DataTypeInfo{0x0009, "VISIBLE_STRING", 0, Kind::kString},
    DataTypeInfo{0x000A, "OCTET_STRING", 0, Kind::kString},
    DataTypeInfo{0x000B, "UNICODE_STRING", 0, Kind::kString},
    DataTypeInfo{0x000C, "TIME_OF_DAY", 48, Kind::kTime},
    DataTypeInfo{0x000D, "TIME_DIFFERENCE", 48, Kind::kTime},
    DataTypeInfo{0x000F, "DOMAIN", 0, Kind::kDomain},
    DataTypeInfo{0x0010, "INTEGER24", 24, Kind::kSigned},
    DataTypeInfo{0x0011, "REAL64", 64, Kind::kReal},
    DataTypeInfo{0x0012, "INTEGER40", 40, Kind::kSigned},
    DataTypeInfo{0x0013, "INTEGER48", 48, Kind::kSigned},
    DataTypeInfo{0x0014, "INTEGER56", 56, Kind::kSigned},
    DataTypeInfo{0x0015, "INTEGER64", 64, Kind::kSigned},
    DataTypeInfo{0x0016, "UNSIGNED24", 24, Kind::kUnsigned},
    DataTypeInfo{0x0018, "UNSIGNED40", 40, Kind::kUnsigned},
    DataTypeInfo{0x0019, "UNSIGNED48", 48, Kind::kUnsigned},
    DataTypeInfo{0x001A, "UNSIGNED56", 56, Kind::kUnsigned},
    DataTypeInfo{0x001B, "UNSIGNED64", 64, Kind::kUnsigned},
};

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) != b[i]) return false;
  }
  return true;
}

}  // namespace

const DataTypeInfo* find_data_type(std::uint16_t code) {
  for (const DataTypeInfo& type : kDataTypes) {
    if (type.code == code) return &type;
  }
  return nullptr;
}

std::optional<AccessType> parse_access_type(std::string_view text) {
  constexpr std::array<std::pair<std::string_view, AccessType>, 6> kNames = {{
      {"ro", AccessType::kRo},
      {"wo", AccessType::kWo},
      {"rw", AccessType::kRw},
      {"rwr", AccessType::kRwr},
      {"rww", AccessType::kRww},
      {"const", AccessType::kConst},
  }};
  for (const auto& [name, access] : kNames) {
    if (equals_ignoring_case(text, name)) return access;
  }
  return std::nullopt;
}

std::string_view to_string(AccessType access) {
  switch (access) {
    case AccessType::kRo:
      return "ro";
    case AccessType::kWo:
      return "wo";
    case AccessType::kRw:
      return "rw";
    case AccessType::kRwr:
      return "rwr";
    case AccessType::kRww:
      return "rww";
    case AccessType::kConst:
      return "const";
  }
  return "?";
}

std::optional<ObjectType> object_type_of(std::uint64_t code) {
  switch (code) {
    case 0x0:
    case 0x2:
    case 0x5:
    case 0x6:
    case 0x7:
    case 0x8:
    case 0x9:
      return static_cast<ObjectType>(code);
    default:
      return std::nullopt;
  }
}

std::string_view to_string(ObjectType type) {
  switch (type) {
    case ObjectType::kNull:
      return "NULL";
    case ObjectType::kDomain:
      return "DOMAIN";
    case ObjectType::kDefType:
      return "DEFTYPE";
    case ObjectType::kDefStruct:
      return "DEFSTRUCT";
    case ObjectType::kVar:
      return "VAR";
    case ObjectType::kArray:
      return "ARRAY";
    case ObjectType::kRecord:
      return "RECORD";
  }
  return "?";
}

}  // namespace cambio::canopen::eds
