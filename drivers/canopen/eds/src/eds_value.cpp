#include "cambio/canopen/eds/eds_value.hpp"

#include <cctype>
#include <limits>

#include "cambio/canopen/eds/eds_data_type.hpp"

namespace cambio::canopen::eds {

namespace {

int digit_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return 99;
}

bool is_node_id(std::string_view text) {
  constexpr std::string_view kNodeId = "$nodeid";
  if (text.size() != kNodeId.size()) return false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(text[i])) != kNodeId[i]) return false;
  }
  return true;
}

}  // namespace

std::optional<std::uint64_t> parse_unsigned(std::string_view text) {
  text = trim(text);
  unsigned base = 10;
  if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
    base = 16;
    text.remove_prefix(2);
  } else if (text.size() > 1 && text[0] == '0') {
    base = 8;
    text.remove_prefix(1);
  }
  if (text.empty()) return std::nullopt;
  std::uint64_t value = 0;
  for (const char c : text) {
    const int digit = digit_value(c);
    if (digit >= static_cast<int>(base)) return std::nullopt;
    if (value > (std::numeric_limits<std::uint64_t>::max() - static_cast<unsigned>(digit)) / base) {
      return std::nullopt;
    }
    value = value * base + static_cast<unsigned>(digit);
  }
  return value;
}

std::optional<EdsInteger> parse_integer(std::string_view text) {
  EdsInteger result;
  int terms = 0;
  bool wide_literal = false;  // An UNSIGNED64 literal above INT64_MAX: only alone.
  bool negative = false;
  std::size_t i = 0;
  const std::string_view leading = trim(text);
  if (!leading.empty() && (leading.front() == '-' || leading.front() == '+')) {
    negative = leading.front() == '-';
    i = static_cast<std::size_t>(leading.data() - text.data()) + 1;
  }
  while (true) {
    std::size_t end = i;
    while (end < text.size() && text[end] != '+' && text[end] != '-') ++end;
    const std::string_view term = trim(text.substr(i, end - i));
    ++terms;
    if (is_node_id(term)) {
      result.node_id_terms += negative ? -1 : 1;
      if (result.node_id_terms > 16 || result.node_id_terms < -16) return std::nullopt;
    } else {
      const auto value = parse_unsigned(term);
      if (!value) return std::nullopt;
      constexpr auto kMax = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
      if (*value > kMax) {
        if (negative) return std::nullopt;
        wide_literal = true;
        result.constant = static_cast<std::int64_t>(*value);  // The raw bits, two's complement.
      } else {
        const auto magnitude = static_cast<std::int64_t>(*value);
        std::int64_t sum = 0;
        if (negative ? __builtin_sub_overflow(result.constant, magnitude, &sum)
                     : __builtin_add_overflow(result.constant, magnitude, &sum)) {
          return std::nullopt;
        }
        result.constant = sum;
      }
    }
    if (wide_literal && terms > 1) return std::nullopt;
    if (end >= text.size()) break;
    negative = text[end] == '-';
    i = end + 1;
  }
  return result;
}

bool fits(std::int64_t value, const DataTypeInfo& type) {
  if (type.bits >= 64 || type.bits <= 0) return true;
  const std::int64_t span = std::int64_t{1} << type.bits;
  const std::int64_t low = type.kind == DataTypeInfo::Kind::kSigned ? -(span / 2) : 0;
  return value >= low && value <= span - 1;
}

std::int64_t as_type(std::int64_t value, const DataTypeInfo& type) {
  if (type.bits >= 64 || type.bits <= 0) return value;
  const auto mask = (std::uint64_t{1} << type.bits) - 1;
  const std::uint64_t bits = static_cast<std::uint64_t>(value) & mask;
  if (type.kind == DataTypeInfo::Kind::kSigned && (bits >> (type.bits - 1)) != 0) {
    return static_cast<std::int64_t>(bits | ~mask);
  }
  return static_cast<std::int64_t>(bits);
}

std::string_view trim(std::string_view text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) {
    text.remove_prefix(1);
  }
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) {
    text.remove_suffix(1);
  }
  return text;
}

}  // namespace cambio::canopen::eds
