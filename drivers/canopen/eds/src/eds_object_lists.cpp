// CiA 306 §4.5: [MandatoryObjects], [OptionalObjects] and [ManufacturerObjects] each hold
// SupportedObjects=N and the keys 1..N naming an object index. Every listed object needs its
// section and every object section needs to be listed; manufacturer-specific objects are those
// of 0x2000..0x5FFF.
#include <array>

#include "eds_reader.hpp"

namespace cambio::canopen::eds {

namespace {

struct ListSpec {
  std::string_view name;
  ObjectList list;
};

constexpr std::array<ListSpec, 3> kLists = {{
    {"MandatoryObjects", ObjectList::kMandatory},
    {"OptionalObjects", ObjectList::kOptional},
    {"ManufacturerObjects", ObjectList::kManufacturer},
}};

std::string hex4(std::uint64_t index) {
  constexpr std::string_view kDigits = "0123456789ABCDEF";
  std::string text = "0x0000";
  for (int i = 0; i < 4; ++i) text[5 - i] = kDigits[(index >> (4 * i)) & 0xF];
  return text;
}

bool manufacturer_specific(std::uint64_t index) {
  return index >= 0x2000 && index <= 0x5FFF;
}

void read_list(const SectionReader& reader, ObjectList list, EdsFile& eds) {
  const IniKey* supported = reader.required("SupportedObjects");
  // A plain count, not an optional: GCC 12 misreads the optional's state here.
  bool has_count = false;
  std::uint64_t count = 0;
  if (supported != nullptr) {
    if (const auto value = reader.number(*supported, "SupportedObjects", 0xFFFF)) {
      has_count = true;
      count = *value;
    }
  }
  const std::string positions =
      "1.." + (has_count ? std::to_string(count) : std::string("SupportedObjects"));
  std::uint64_t entries = 0;
  for (const IniKey& key : reader.section().keys) {
    if (key.name == "supportedobjects") continue;
    const auto position = parse_unsigned(key.name);
    if (!position || key.name.front() == '0' ||
        (has_count && (*position < 1 || *position > count))) {
      reader.issue(key.line, "key " + key.name + ": expected a position " + positions);
      continue;
    }
    ++entries;
    const auto index = reader.number(key, key.name, 0xFFFF);
    if (!index) continue;
    const bool vendor_list = list == ObjectList::kManufacturer;
    if (manufacturer_specific(*index) != vendor_list) {
      reader.issue(key.line, hex4(*index) + (vendor_list ? " is not manufacturer-specific "
                                                           "(0x2000..0x5FFF): list it in "
                                                           "[OptionalObjects]"
                                                         : " is manufacturer-specific: list it "
                                                           "in [ManufacturerObjects]"));
    }
    const auto index16 = static_cast<std::uint16_t>(*index);
    if (!eds.listed.emplace(index16, list).second) {
      reader.issue(key.line, hex4(*index) + " is listed twice");
    } else if (eds.find(index16) == nullptr) {
      reader.issue(key.line, hex4(*index) + " is listed, but no [" + hex4(*index).substr(2) +
                                 "] section describes it");
    }
  }
  if (has_count && entries != count) {
    reader.issue(supported->line, "SupportedObjects=" + supported->value + " but " +
                                      std::to_string(entries) + " objects are listed");
  }
}

}  // namespace

void read_object_lists(const IniDocument& document, EdsFile& eds, std::vector<EdsIssue>& issues) {
  for (const ListSpec& spec : kLists) {
    const IniSection* section = document.find(lower_case(spec.name));
    if (section == nullptr) {
      if (spec.list != ObjectList::kManufacturer) {
        issues.push_back({eds.file, 0, "no [" + std::string(spec.name) + "] section"});
      }
      continue;
    }
    read_list(SectionReader(*section, eds.file, issues), spec.list, eds);
  }
  for (const auto& [index, object] : eds.objects) {
    if (eds.listed.contains(index)) continue;
    issues.push_back({eds.file, object.line,
                      "object [" + hex4(index).substr(2) + "] is in none of " +
                          (manufacturer_specific(index) ? "[ManufacturerObjects]"
                                                        : "[MandatoryObjects], [OptionalObjects]") +
                          ": list it there"});
  }
}

}  // namespace cambio::canopen::eds
