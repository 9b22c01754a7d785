// The object sections of an EDS: [XXXX] for an object, [XXXXsubN] for a sub-index (N in hex,
// "sub" in any case), [XXXXName]/[XXXXValue] for a CompactSubObj array's names and a DCF's
// values (known, not needed here). Other sections ([FileInfo], a vendor's tool sections) are
// not about objects.
#include <cctype>
#include <map>
#include <set>
#include <utility>

#include "eds_reader.hpp"

namespace cambio::canopen::eds {

namespace {

bool is_hex(std::string_view text) {
  for (const char c : text) {
    if (!std::isxdigit(static_cast<unsigned char>(c))) return false;
  }
  return !text.empty();
}

std::uint32_t hex_value(std::string_view text) {
  return static_cast<std::uint32_t>(parse_unsigned("0x" + std::string(text)).value_or(0));
}

struct SubSection {
  std::uint8_t subindex = 0;
  const IniSection* section = nullptr;
};

/// An ARRAY or RECORD with CompactSubObj=N (CiA 306 §4.5.2.3): sub 0 holds N, subs 1..N share
/// the object's DataType, AccessType, PDOMapping and DefaultValue.
void read_compact(const SectionReader& reader, EdsObject& object, std::uint64_t count) {
  EdsEntry highest;
  highest.name = "Highest sub-index supported";
  highest.data_type = find_data_type(0x0005);
  highest.access = AccessType::kRo;
  highest.default_value = EdsInteger{static_cast<std::int64_t>(count), 0};
  highest.default_text = std::to_string(count);
  highest.line = object.line;
  object.entries.emplace(0, highest);
  for (std::uint64_t sub = 1; sub <= count; ++sub) {
    auto entry =
        read_entry(reader, static_cast<std::uint8_t>(sub), object.name + " " + std::to_string(sub));
    if (!entry) return;  // Reported once, at the object's keys.
    object.entries.emplace(static_cast<std::uint8_t>(sub), std::move(*entry));
  }
  object.sub_number = static_cast<int>(count) + 1;
}

void read_subs(const SectionReader& reader, EdsObject& object, const std::vector<SubSection>& subs,
               const std::string& file, std::vector<EdsIssue>& issues) {
  const IniKey* sub_number = reader.required("SubNumber");
  if (sub_number != nullptr) {
    const auto count = reader.number(*sub_number, "SubNumber", 0xFF + 1);
    object.sub_number = static_cast<int>(count.value_or(0));
    if (count && *count != subs.size()) {
      reader.issue(sub_number->line, "SubNumber=" + sub_number->value + " but " +
                                         std::to_string(subs.size()) + " sub-index sections [" +
                                         reader.section().name + "subN] are present");
    }
  }
  std::set<std::uint8_t> seen;
  for (const SubSection& sub : subs) {
    const SectionReader sub_reader(*sub.section, file, issues);
    const IniKey* name = sub_reader.required("ParameterName");
    if (const IniKey* type = sub_reader.optional("ObjectType")) {
      const auto code = sub_reader.number(*type, "ObjectType", 0xFF);
      if (code && *code != static_cast<std::uint64_t>(ObjectType::kVar) &&
          *code != static_cast<std::uint64_t>(ObjectType::kDomain)) {
        sub_reader.issue(type->line, "ObjectType " + type->value +
                                         ": a sub-index is a VAR (0x7) or DOMAIN (0x2)");
      }
    }
    auto entry = read_entry(sub_reader, sub.subindex, name != nullptr ? name->value : "");
    if (!seen.insert(sub.subindex).second) {
      sub_reader.issue(sub.section->line,
                       "sub-index " + std::to_string(sub.subindex) + " is described twice");
    } else if (entry && name != nullptr) {
      object.entries.emplace(sub.subindex, std::move(*entry));
    }
  }
  if (!subs.empty() && !seen.contains(0)) {
    reader.issue(object.line, "no [" + reader.section().name +
                                  "sub0] (highest sub-index supported), which an " +
                                  std::string(to_string(object.type)) + " needs");
  }
}

}  // namespace

void read_objects(const IniDocument& document, EdsFile& eds, std::vector<EdsIssue>& issues) {
  std::map<std::uint16_t, const IniSection*> object_sections;
  std::map<std::uint16_t, std::vector<SubSection>> sub_sections;
  for (const IniSection& section : document.sections) {
    const std::string_view name = section.lower_name;
    if (name.size() < 4 || !is_hex(name.substr(0, 4))) continue;
    const auto index = static_cast<std::uint16_t>(hex_value(name.substr(0, 4)));
    const std::string_view rest = name.substr(4);
    if (rest.empty()) {
      object_sections.emplace(index, &section);
    } else if (rest.starts_with("sub") && rest.size() <= 5 && is_hex(rest.substr(3))) {
      sub_sections[index].push_back(
          {static_cast<std::uint8_t>(hex_value(rest.substr(3))), &section});
    } else if (rest != "name" && rest != "value" && rest != "denotation") {
      issues.push_back({eds.file, section.line,
                        "section [" + section.name +
                            "]: expected an object [XXXX] or a sub-index [XXXXsubN] (hex)"});
    }
  }
  for (const auto& [index, subs] : sub_sections) {
    if (object_sections.contains(index)) continue;
    for (const SubSection& sub : subs) {
      issues.push_back({eds.file, sub.section->line,
                        "sub-index section [" + sub.section->name + "] without its object [" +
                            sub.section->name.substr(0, 4) + "]"});
    }
  }
  for (const auto& [index, section] : object_sections) {
    const SectionReader reader(*section, eds.file, issues);
    EdsObject object;
    object.index = index;
    object.line = section->line;
    if (const IniKey* name = reader.required("ParameterName")) object.name = name->value;
    if (const IniKey* type_key = reader.optional("ObjectType")) {
      const auto code = reader.number(*type_key, "ObjectType", 0xFF);
      const auto type = code ? object_type_of(*code) : std::nullopt;
      if (code && !type) {
        reader.issue(type_key->line, "ObjectType " + type_key->value +
                                         ": expected 0x7 (VAR), 0x8 (ARRAY), 0x9 (RECORD), 0x2 "
                                         "(DOMAIN), 0x5, 0x6 or 0x0");
      }
      object.type = type.value_or(ObjectType::kVar);
    }
    const auto subs_it = sub_sections.find(index);
    const std::vector<SubSection> no_subs;
    const std::vector<SubSection>& subs = subs_it == sub_sections.end() ? no_subs : subs_it->second;
    const IniKey* compact = reader.optional("CompactSubObj");
    const std::uint64_t compact_count =
        compact != nullptr ? reader.number(*compact, "CompactSubObj", 0xFE).value_or(0) : 0;
    if (object.type == ObjectType::kNull) {
      // A placeholder: no value.
    } else if (!has_sub_sections(object.type)) {
      for (const SubSection& sub : subs) {
        issues.push_back({eds.file, sub.section->line,
                          "sub-index section [" + sub.section->name + "] under " +
                              std::string(to_string(object.type)) + " object [" + section->name +
                              "] (line " + std::to_string(section->line) +
                              "), which has no sub-indices"});
      }
      auto entry = read_entry(reader, 0, object.name);
      if (entry) object.entries.emplace(0, std::move(*entry));
    } else if (compact_count > 0) {
      read_compact(reader, object, compact_count);
    } else {
      read_subs(reader, object, subs, eds.file, issues);
    }
    eds.objects.emplace(index, std::move(object));
  }
}

}  // namespace cambio::canopen::eds
