#pragma once

// A vendor's electronic data sheet (CiA 306 v1.3, the INI form) read into a description of the
// drive's object dictionary: every object by index with its sub-indices ([1018], [1018sub1],
// CompactSubObj arrays), each entry's data type, access, PDO mapping, default value (with
// $NODEID terms kept for evaluation per node) and limits; the PDO counts of [DeviceInfo]; and the
// object lists checked against the sections present.
//
// Errors are values: every malformed thing is an EdsIssue naming file:line, all of them in one
// pass. Nothing here throws on bad input (only std::bad_alloc can escape), and the reader never
// reads outside the text it is given: it is meant to be fuzzed.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/canopen/eds/eds_data_type.hpp"
#include "cambio/canopen/eds/eds_issue.hpp"
#include "cambio/canopen/eds/eds_value.hpp"
#include "cambio/canopen/protocol.hpp"

namespace cambio::canopen::eds {

/// One value of the dictionary: a VAR object (sub-index 0) or a sub-index of an ARRAY/RECORD.
struct EdsEntry {
  std::uint8_t subindex = 0;
  std::string name;                         ///< ParameterName.
  const DataTypeInfo* data_type = nullptr;  ///< Never null in a parsed file.
  AccessType access = AccessType::kRo;
  bool pdo_mappable = false;                ///< PDOMapping=1.
  std::string default_text;                 ///< DefaultValue as written ("" when absent).
  std::optional<EdsInteger> default_value;  ///< DefaultValue of an integer type.
  std::optional<EdsInteger> low_limit;      ///< LowLimit of an integer type.
  std::optional<EdsInteger> high_limit;     ///< HighLimit of an integer type.
  int line = 0;                             ///< Its section's line.
};

struct EdsObject {
  std::uint16_t index = 0;
  std::string name;  ///< ParameterName.
  ObjectType type = ObjectType::kVar;
  int sub_number = 0;                        ///< SubNumber (0 for a VAR).
  int line = 0;                              ///< The line of its [index] section.
  std::map<std::uint8_t, EdsEntry> entries;  ///< By sub-index; a VAR has sub-index 0 alone.
};

/// Which object list of the file names an object (CiA 306 §4.5).
enum class ObjectList : std::uint8_t { kMandatory, kOptional, kManufacturer };

struct EdsFile {
  std::string file;  ///< The path (or name) issues are located in.
  std::map<std::uint16_t, EdsObject> objects;
  /// [DeviceInfo] NrOfRXPDO / NrOfTXPDO; nullopt when the file does not say.
  std::optional<int> rx_pdos;
  std::optional<int> tx_pdos;
  int device_info_line = 0;
  std::map<std::uint16_t, ObjectList> listed;  ///< Every index the object lists name.

  const EdsObject* find(std::uint16_t index) const {
    const auto it = objects.find(index);
    return it == objects.end() ? nullptr : &it->second;
  }
  const EdsEntry* find(ObjectAddress address) const {
    const EdsObject* object = find(address.index);
    if (object == nullptr) return nullptr;
    const auto it = object->entries.find(address.subindex);
    return it == object->entries.end() ? nullptr : &it->second;
  }
};

struct EdsReadResult {
  EdsFile eds;                   ///< What could be read, also when there are issues.
  std::vector<EdsIssue> issues;  ///< Empty when the file is well formed.
  bool ok() const { return issues.empty(); }
};

/// Parses EDS `text`, locating issues in `file`.
EdsReadResult parse_eds(std::string_view text, std::string file);

/// Reads and parses the file at `path`; an unreadable file is one issue at line 0.
EdsReadResult read_eds_file(const std::string& path);

}  // namespace cambio::canopen::eds
