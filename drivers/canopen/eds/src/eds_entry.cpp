#include <string>

#include "eds_reader.hpp"

namespace cambio::canopen::eds {

namespace {

std::string in_quotes(std::string_view text) {
  return "'" + std::string(text.substr(0, 60)) + (text.size() > 60 ? "...'" : "'");
}

std::string range_text(const DataTypeInfo& type) {
  if (type.bits >= 64)
    return type.kind == DataTypeInfo::Kind::kSigned ? "64-bit signed" : "64 bits";
  const std::int64_t span = std::int64_t{1} << type.bits;
  const std::int64_t low = type.kind == DataTypeInfo::Kind::kSigned ? -(span / 2) : 0;
  return std::to_string(low) + ".." + std::to_string(span - 1);
}

/// An integer value key (DefaultValue, LowLimit, HighLimit) of an integer type: a number or
/// $NODEID expression that fits the type for every node id 1..127.
std::optional<EdsInteger> integer_value(const SectionReader& reader, const IniKey& key,
                                        std::string_view spelled, const DataTypeInfo& type) {
  const auto value = parse_integer(key.value);
  if (!value) {
    reader.issue(key.line, std::string(spelled) +
                               ": expected a number (decimal, 0x hex, or with $NODEID as in "
                               "$NODEID+0x180), found " +
                               in_quotes(key.value));
    return std::nullopt;
  }
  for (const int node_id : {kMinNodeId, kMaxNodeId}) {
    if (!fits(value->evaluate(node_id), type)) {
      reader.issue(key.line,
                   std::string(spelled) + " " + key.value +
                       (value->depends_on_node_id() ? " (for node " + std::to_string(node_id) + ")"
                                                    : std::string()) +
                       " does not fit " + std::string(type.name) + " (" + range_text(type) + ")");
      return std::nullopt;
    }
  }
  return value;
}

}  // namespace

const IniKey* SectionReader::optional(std::string_view spelled) const {
  return section_.find(lower_case(spelled));
}

const IniKey* SectionReader::required(std::string_view spelled) const {
  const IniKey* key = optional(spelled);
  if (key == nullptr) issue(section_.line, "missing " + std::string(spelled) + "=");
  return key;
}

std::optional<std::uint64_t> SectionReader::number(const IniKey& key, std::string_view spelled,
                                                   std::uint64_t max) const {
  const auto value = parse_unsigned(key.value);
  if (!value || *value > max) {
    issue(key.line, std::string(spelled) + ": expected a number 0.." + std::to_string(max) +
                        " (decimal or 0x hex), found " + in_quotes(key.value));
    return std::nullopt;
  }
  return value;
}

std::optional<EdsEntry> read_entry(const SectionReader& reader, std::uint8_t subindex,
                                   std::string name) {
  EdsEntry entry;
  entry.subindex = subindex;
  entry.name = std::move(name);
  entry.line = reader.section().line;
  bool complete = true;
  if (const IniKey* key = reader.required("DataType")) {
    if (const auto code = reader.number(*key, "DataType", 0xFFFF)) {
      entry.data_type = find_data_type(static_cast<std::uint16_t>(*code));
      if (entry.data_type == nullptr) {
        reader.issue(key->line, "DataType " + key->value +
                                    ": unknown data type (CiA 301 defines 0x0001 BOOLEAN .. "
                                    "0x001B UNSIGNED64, e.g. 0x0007 UNSIGNED32)");
      }
    }
  }
  complete = complete && entry.data_type != nullptr;
  if (const IniKey* key = reader.required("AccessType")) {
    if (const auto access = parse_access_type(key->value)) {
      entry.access = *access;
    } else {
      reader.issue(key->line, "AccessType: expected ro, wo, rw, rwr, rww or const, found " +
                                  in_quotes(key->value));
      complete = false;
    }
  } else {
    complete = false;
  }
  if (const IniKey* key = reader.optional("PDOMapping")) {
    const auto mapping = reader.number(*key, "PDOMapping", 1);
    entry.pdo_mappable = mapping.value_or(0) == 1;
    complete = complete && mapping.has_value();
  }
  if (entry.data_type == nullptr) return std::nullopt;
  const DataTypeInfo& type = *entry.data_type;
  const IniKey* default_key = reader.optional("DefaultValue");
  if (default_key != nullptr) entry.default_text = default_key->value;
  if (type.is_integer()) {
    if (default_key != nullptr && !default_key->value.empty()) {
      entry.default_value = integer_value(reader, *default_key, "DefaultValue", type);
      complete = complete && entry.default_value.has_value();
    }
    const IniKey* low_key = reader.optional("LowLimit");
    const IniKey* high_key = reader.optional("HighLimit");
    if (low_key != nullptr && !low_key->value.empty()) {
      entry.low_limit = integer_value(reader, *low_key, "LowLimit", type);
      complete = complete && entry.low_limit.has_value();
    }
    if (high_key != nullptr && !high_key->value.empty()) {
      entry.high_limit = integer_value(reader, *high_key, "HighLimit", type);
      complete = complete && entry.high_limit.has_value();
    }
    // Limits and default compared for the first node; a drive holds the type's view of them.
    const auto at = [&type](const EdsInteger& value) {
      return as_type(value.evaluate(kMinNodeId), type);
    };
    if (entry.low_limit && entry.high_limit && at(*entry.low_limit) > at(*entry.high_limit)) {
      reader.issue(high_key->line, "HighLimit " + high_key->value + " is below LowLimit " +
                                       low_key->value + " (line " + std::to_string(low_key->line) +
                                       ")");
      complete = false;
    }
    if (entry.default_value &&
        ((entry.low_limit && at(*entry.default_value) < at(*entry.low_limit)) ||
         (entry.high_limit && at(*entry.default_value) > at(*entry.high_limit)))) {
      reader.issue(default_key->line,
                   "DefaultValue " + default_key->value + " is outside LowLimit..HighLimit");
      complete = false;
    }
  }
  if (!complete) return std::nullopt;
  return entry;
}

}  // namespace cambio::canopen::eds
