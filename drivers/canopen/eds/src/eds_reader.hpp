#pragma once

// The steps of parse_eds (eds_file.cpp) over the INI document, each adding what it reads to the
// EdsFile and every problem to the issues; and the key reader they share.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/canopen/eds/eds_file.hpp"
#include "cambio/canopen/eds/eds_ini.hpp"

namespace cambio::canopen::eds {

/// Reads keys of one section, reporting "[Section] Key: expected ..., found ..." at their line.
class SectionReader {
 public:
  SectionReader(const IniSection& section, const std::string& file, std::vector<EdsIssue>& issues)
      : section_(section), file_(file), issues_(issues) {}

  const IniSection& section() const { return section_; }
  void issue(int line, const std::string& message) const {
    issues_.push_back({file_, line, "[" + section_.name + "] " + message});
  }
  /// The key `spelled` (its CiA 306 spelling, looked up in any case), or an issue at the
  /// section's line and nullptr.
  const IniKey* required(std::string_view spelled) const;
  const IniKey* optional(std::string_view spelled) const;
  /// The key's value as a plain whole number at most `max`, else an issue and nullopt.
  std::optional<std::uint64_t> number(const IniKey& key, std::string_view spelled,
                                      std::uint64_t max) const;

 private:
  const IniSection& section_;
  const std::string& file_;
  std::vector<EdsIssue>& issues_;
};

/// One value's keys (DataType, AccessType, PDOMapping, DefaultValue, LowLimit, HighLimit): an
/// entry, or nullopt when a key it needs is missing or malformed (each reported).
std::optional<EdsEntry> read_entry(const SectionReader& reader, std::uint8_t subindex,
                                   std::string name);

/// Every [XXXX] and [XXXXsubN] section (eds_objects.cpp).
void read_objects(const IniDocument& document, EdsFile& eds, std::vector<EdsIssue>& issues);

/// [MandatoryObjects], [OptionalObjects], [ManufacturerObjects] against the sections present
/// (eds_object_lists.cpp).
void read_object_lists(const IniDocument& document, EdsFile& eds, std::vector<EdsIssue>& issues);

}  // namespace cambio::canopen::eds
