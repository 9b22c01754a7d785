#include "cambio/config/map_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <tuple>

#include "format.hpp"

namespace cambio::config {

// ---------------------------------------------------------------------------------------------
// IssueList

namespace {

/// True when `path` is `prefix` or lies under it ("a.b" is under "a", so is "a[2]").
bool is_at_or_under(std::string_view path, std::string_view prefix) {
  if (!path.starts_with(prefix)) return false;
  return path.size() == prefix.size() || path[prefix.size()] == '.' || path[prefix.size()] == '[';
}

}  // namespace

void IssueList::add(ConfigIssue issue) {
  issues_.push_back(located(std::move(issue)));
}

ConfigIssue IssueList::located(ConfigIssue issue) const {
  for (const auto& overridden : overridden_paths_) {
    if (is_at_or_under(issue.key_path, overridden)) {
      issue.file = "--set";
      issue.line = 0;
      issue.column = 0;
      break;
    }
  }
  return issue;
}

void IssueList::mark_overridden(std::string key_path) {
  overridden_paths_.push_back(std::move(key_path));
}

void IssueList::mark_created(std::string key_path, std::vector<std::string> file_keys) {
  created_maps_.push_back({key_path, std::move(file_keys)});
  mark_overridden(std::move(key_path));
}

void IssueList::throw_if_any() const {
  if (issues_.empty()) return;
  // Keys missing under a map that only an override made up point at the override's typo.
  std::vector<ConfigIssue> sorted;
  std::vector<std::vector<std::string>> missing(created_maps_.size());
  for (const auto& issue : issues_) {
    const auto created =
        std::find_if(created_maps_.begin(), created_maps_.end(), [&issue](const CreatedMap& map) {
          return issue.key_path.size() > map.key_path.size() &&
                 is_at_or_under(issue.key_path, map.key_path) &&
                 issue.message.starts_with(kMissingKey);
        });
    if (created == created_maps_.end()) {
      sorted.push_back(issue);
      continue;
    }
    const auto index = static_cast<std::size_t>(created - created_maps_.begin());
    missing[index].push_back(issue.key_path.substr(created->key_path.size() + 1));
  }
  for (std::size_t i = 0; i < created_maps_.size(); ++i) {
    if (missing[i].empty()) continue;
    const CreatedMap& map = created_maps_[i];
    const std::string name = map.key_path.substr(map.key_path.rfind('.') + 1);
    std::string message = "--set made up " + in_quotes(name) +
                          ", which the file does not have, and it lacks " + join(missing[i]);
    if (const auto suggestion = closest_name(name, map.file_keys)) {
      message += "; did you mean " + in_quotes(*suggestion) + "?";
    } else if (!map.file_keys.empty()) {
      message += "; the file has " + join(map.file_keys);
    }
    sorted.push_back(ConfigIssue{"--set", 0, 0, map.key_path, std::move(message)});
  }
  std::stable_sort(sorted.begin(), sorted.end(), [](const ConfigIssue& a, const ConfigIssue& b) {
    return std::tie(a.file, a.line, a.column) < std::tie(b.file, b.line, b.column);
  });
  throw ConfigError(std::move(sorted));
}

// ---------------------------------------------------------------------------------------------
// Range

bool Range::contains(double value) const {
  const bool above_min = min_exclusive ? value > min : value >= min;
  const bool below_max = max_exclusive ? value < max : value <= max;
  return above_min && below_max;
}

std::string Range::describe() const {
  const bool has_min = std::isfinite(min);
  const bool has_max = std::isfinite(max);
  if (has_min && has_max) {
    return std::string("in ") + (min_exclusive ? "(" : "[") + format_number(min) + ", " +
           format_number(max) + (max_exclusive ? ")" : "]");
  }
  if (has_min) return (min_exclusive ? "> " : ">= ") + format_number(min);
  if (has_max) return (max_exclusive ? "< " : "<= ") + format_number(max);
  return "";
}

// ---------------------------------------------------------------------------------------------
// MapReader

namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

/// "a number > 0", "an integer in [1, 127]", "a number".
std::string expected(std::string_view what, const Range& range) {
  const std::string bounds = range.describe();
  return std::string(what) + (bounds.empty() ? "" : " " + bounds);
}

/// "expected a number in [0, 1], found "x"" for a value of the wrong kind; for a number out of
/// range, "expected a number in [0, 1] (<the range's reason>), found 2".
std::string unexpected(std::string_view what, const Range& range, bool is_number,
                       const std::string& found_text) {
  std::string message = "expected " + expected(what, range);
  if (is_number && !range.reason.empty()) message += " (" + std::string(range.reason) + ")";
  return message + ", found " + found_text;
}

Range scaled(const Range& range, double factor) {
  return {range.min * factor, range.max * factor, range.min_exclusive, range.max_exclusive,
          range.reason};
}

bool is_plain_scalar(const YAML::Node& node) {
  // yaml-cpp tags quoted scalars "!" and plain ones "?": "2.0" in quotes is text, not a number.
  return node.IsScalar() && node.Tag() != "!";
}

std::optional<double> parse_number(const YAML::Node& node) {
  if (!is_plain_scalar(node)) return std::nullopt;
  std::string_view text = node.Scalar();
  if (text.starts_with('+')) text.remove_prefix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size() || text.empty() ||
      !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

std::optional<std::int64_t> parse_integer(const YAML::Node& node) {
  if (!is_plain_scalar(node)) return std::nullopt;
  std::string_view text = node.Scalar();
  if (text.starts_with('+')) text.remove_prefix(1);
  std::int64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size() || text.empty()) {
    return std::nullopt;
  }
  return value;
}

std::optional<bool> parse_boolean(const YAML::Node& node) {
  if (!is_plain_scalar(node)) return std::nullopt;
  const std::string& text = node.Scalar();
  if (text == "true" || text == "True" || text == "TRUE") return true;
  if (text == "false" || text == "False" || text == "FALSE") return false;
  return std::nullopt;
}

/// How a node reads in "found ..." messages.
std::string found(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      return is_plain_scalar(node) && parse_number(node) ? echoed(node.Scalar())
                                                         : in_quotes(node.Scalar());
    case YAML::NodeType::Sequence:
      return "a list of " + std::to_string(node.size());
    case YAML::NodeType::Map:
      return "a map";
    default:
      return "nothing";
  }
}

}  // namespace

MapReader::MapReader(YAML::Node node, std::string key_path, std::string file,
                     std::shared_ptr<IssueList> issues)
    : MapReader(node, std::move(key_path), std::move(file), std::move(issues),
                node.IsDefined() ? node.Mark() : YAML::Mark::null_mark()) {}

MapReader::MapReader(YAML::Node node, std::string key_path, std::string file,
                     std::shared_ptr<IssueList> issues, YAML::Mark mark)
    : node_(node),
      mark_(mark),
      key_path_(std::move(key_path)),
      file_(std::move(file)),
      issues_(std::move(issues)) {
  if (!node_.IsMap()) {
    record(mark_, key_path_, "expected a map, found " + found(node_));
    valid_ = false;
    return;
  }
  // yaml-cpp keeps both entries of a repeated key and lookups see only the first: refuse it.
  std::map<std::string, int, std::less<>> first_line;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (!it->first.IsScalar()) continue;  // Reported by finish() as an unknown key.
    const std::string& key = it->first.Scalar();
    const auto [previous, inserted] = first_line.emplace(key, it->first.Mark().line + 1);
    if (!inserted) {
      record(it->first.Mark(), child_path(key),
             "duplicate key (first given at line " + std::to_string(previous->second) + ")");
    }
  }
}

MapReader MapReader::silent(std::string key_path) const {
  MapReader reader(YAML::Node(YAML::NodeType::Map), std::move(key_path), file_, issues_, mark_);
  reader.valid_ = false;
  return reader;
}

std::string MapReader::child_path(std::string_view key) const {
  if (key.empty()) return key_path_;
  if (key_path_.empty()) return std::string(key);
  return key_path_ + "." + std::string(key);
}

void MapReader::record(const YAML::Mark& at, std::string key_path, std::string message) {
  const bool known = !at.is_null() && at.line >= 0;
  issues_->add(ConfigIssue{file_, known ? at.line + 1 : 0, known ? at.column + 1 : 0,
                           std::move(key_path), std::move(message)});
}

ConfigIssue MapReader::location_of(std::string_view key) const {
  YAML::Mark at = mark_;
  if (valid_) {
    for (auto it = node_.begin(); it != node_.end(); ++it) {
      if (it->first.IsScalar() && it->first.Scalar() == key) {
        at = mark_of(Entry{it->first, it->second});
        break;
      }
    }
  }
  const bool known = !at.is_null() && at.line >= 0;
  return issues_->located(
      ConfigIssue{file_, known ? at.line + 1 : 0, known ? at.column + 1 : 0, child_path(key), {}});
}

void MapReader::record_locations(std::map<std::string, ConfigIssue, std::less<>>& index) const {
  const bool known = !mark_.is_null() && mark_.line >= 0;
  index[key_path_] = issues_->located(
      ConfigIssue{file_, known ? mark_.line + 1 : 0, known ? mark_.column + 1 : 0, key_path_, {}});
  if (!valid_) return;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (!it->first.IsScalar()) continue;
    ConfigIssue at = location_of(it->first.Scalar());
    index[at.key_path] = std::move(at);
  }
}

YAML::Mark MapReader::mark_of(const Entry& entry) {
  return entry.value.IsNull() || !entry.value.IsDefined() ? entry.key.Mark() : entry.value.Mark();
}

std::optional<MapReader::Entry> MapReader::lookup(std::string_view key) {
  read_keys_.emplace(key);
  if (!valid_) return std::nullopt;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (it->first.IsScalar() && it->first.Scalar() == key) return Entry{it->first, it->second};
  }
  return std::nullopt;
}

bool MapReader::has(std::string_view key) const {
  if (!valid_) return false;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (it->first.IsScalar() && it->first.Scalar() == key) return true;
  }
  return false;
}

bool MapReader::is_list(std::string_view key) const {
  if (!valid_) return false;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (it->first.IsScalar() && it->first.Scalar() == key) return it->second.IsSequence();
  }
  return false;
}

bool MapReader::is_map(std::string_view key) const {
  if (!valid_) return false;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (it->first.IsScalar() && it->first.Scalar() == key) return it->second.IsMap();
  }
  return false;
}

double MapReader::number(std::string_view key, Range range) {
  const auto entry = lookup(key);
  if (!entry) {
    if (valid_)
      record(mark_, child_path(key), "missing key (expected " + expected("a number", range) + ")");
    return std::isfinite(range.min) ? range.min : 0.0;
  }
  return number_or(key, 0.0, range);
}

double MapReader::number_or(std::string_view key, double fallback, Range range) {
  const auto entry = lookup(key);
  if (!entry) return fallback;
  const auto value = parse_number(entry->value);
  if (!value || !range.contains(*value)) {
    record(mark_of(*entry), child_path(key),
           unexpected("a number", range, value.has_value(), found(entry->value)));
    return fallback;
  }
  return *value;
}

std::int64_t MapReader::integer(std::string_view key, Range range) {
  const auto entry = lookup(key);
  if (!entry) {
    if (valid_) {
      record(mark_, child_path(key),
             "missing key (expected " + expected("an integer", range) + ")");
    }
    return std::isfinite(range.min) ? static_cast<std::int64_t>(range.min) : 0;
  }
  return integer_or(key, 0, range);
}

std::int64_t MapReader::integer_or(std::string_view key, std::int64_t fallback, Range range) {
  const auto entry = lookup(key);
  if (!entry) return fallback;
  const auto value = parse_integer(entry->value);
  if (!value || !range.contains(static_cast<double>(*value))) {
    record(mark_of(*entry), child_path(key),
           unexpected("an integer", range, value.has_value(), found(entry->value)));
    return fallback;
  }
  return *value;
}

bool MapReader::boolean(std::string_view key) {
  if (valid_ && !has(key)) {
    lookup(key);
    record(mark_, child_path(key), "missing key (expected true or false)");
    return false;
  }
  return boolean_or(key, false);
}

bool MapReader::boolean_or(std::string_view key, bool fallback) {
  const auto entry = lookup(key);
  if (!entry) return fallback;
  const auto value = parse_boolean(entry->value);
  if (!value) {
    record(mark_of(*entry), child_path(key),
           "expected true or false, found " + found(entry->value));
    return fallback;
  }
  return *value;
}

std::string MapReader::text(std::string_view key) {
  if (valid_ && !has(key)) {
    lookup(key);
    record(mark_, child_path(key), "missing key (expected a name or text)");
    return {};
  }
  return text_or(key, {});
}

std::string MapReader::text_or(std::string_view key, std::string fallback) {
  const auto entry = lookup(key);
  if (!entry) return fallback;
  if (!entry->value.IsScalar() || entry->value.Scalar().empty()) {
    record(mark_of(*entry), child_path(key),
           "expected a name or text, found " + found(entry->value));
    return fallback;
  }
  return entry->value.Scalar();
}

std::string MapReader::choice(std::string_view key,
                              std::initializer_list<std::string_view> allowed) {
  if (valid_ && !has(key)) {
    lookup(key);
    std::vector<std::string> names(allowed.begin(), allowed.end());
    record(mark_, child_path(key), "missing key (expected one of " + join(names) + ")");
    return {};
  }
  return choice_or(key, allowed, {});
}

std::string MapReader::choice_or(std::string_view key,
                                 std::initializer_list<std::string_view> allowed,
                                 std::string fallback) {
  const auto entry = lookup(key);
  if (!entry) return fallback;
  if (entry->value.IsScalar() &&
      std::find(allowed.begin(), allowed.end(), entry->value.Scalar()) != allowed.end()) {
    return entry->value.Scalar();
  }
  std::vector<std::string> names(allowed.begin(), allowed.end());
  record(mark_of(*entry), child_path(key),
         "expected one of " + join(names) + ", found " + found(entry->value));
  return fallback;
}

double MapReader::angle_rad(std::string_view stem, Range range_rad) {
  const std::string rad_key = std::string(stem) + "_rad";
  const std::string deg_key = std::string(stem) + "_deg";
  if (valid_ && !has(rad_key) && !has(deg_key)) {
    lookup(rad_key);
    lookup(deg_key);
    record(mark_, child_path(deg_key), "missing key (expected " + deg_key + " or " + rad_key + ")");
    return std::isfinite(range_rad.min) ? range_rad.min : 0.0;
  }
  return angle_rad_or(stem, 0.0, range_rad);
}

MapReader::AngleUnit MapReader::angle_unit(std::string_view stem) {
  const std::string rad_key = std::string(stem) + "_rad";
  const std::string deg_key = std::string(stem) + "_deg";
  const auto rad_entry = lookup(rad_key);
  const auto deg_entry = lookup(deg_key);
  if (rad_entry && deg_entry) {
    const bool deg_second = deg_entry->key.Mark().pos > rad_entry->key.Mark().pos;
    const auto& second = deg_second ? *deg_entry : *rad_entry;
    record(second.key.Mark(), child_path(deg_second ? deg_key : rad_key),
           "expected either " + deg_key + " or " + rad_key + ", found both");
    return AngleUnit::kBoth;
  }
  if (rad_entry) return AngleUnit::kRad;
  return deg_entry ? AngleUnit::kDeg : AngleUnit::kAbsent;
}

double MapReader::angle_rad_or(std::string_view stem, double fallback_rad, Range range_rad) {
  const std::string rad_key = std::string(stem) + "_rad";
  const std::string deg_key = std::string(stem) + "_deg";
  const AngleUnit unit = angle_unit(stem);
  if (unit == AngleUnit::kRad) return number_or(rad_key, fallback_rad, range_rad);
  if (unit == AngleUnit::kDeg) {
    const double value_deg =
        number_or(deg_key, fallback_rad / kRadPerDeg, scaled(range_rad, 1.0 / kRadPerDeg));
    // Multiply before dividing so that whole degrees give the closed form (90 deg -> pi / 2).
    return value_deg * std::numbers::pi / 180.0;
  }
  return fallback_rad;
}

std::array<double, 3> MapReader::vector3(std::string_view key, Range each) {
  if (valid_ && !has(key)) {
    lookup(key);
    record(mark_, child_path(key), "missing key (expected a list of 3 numbers)");
    return {0.0, 0.0, 0.0};
  }
  return vector3_or(key, {0.0, 0.0, 0.0}, each);
}

std::array<double, 3> MapReader::vector3_or(std::string_view key, std::array<double, 3> fallback,
                                            Range each) {
  const auto entry = lookup(key);
  if (!entry) return fallback;
  if (!entry->value.IsSequence() || entry->value.size() != 3) {
    record(mark_of(*entry), child_path(key),
           "expected a list of 3 numbers, found " + found(entry->value));
    return fallback;
  }
  const std::vector<double> values = numbers(key, each);
  if (values.size() != 3) return fallback;
  return {values[0], values[1], values[2]};
}

std::array<double, 3> MapReader::angles3_rad_or(std::string_view stem,
                                                std::array<double, 3> fallback) {
  const std::string rad_key = std::string(stem) + "_rad";
  const std::string deg_key = std::string(stem) + "_deg";
  const AngleUnit unit = angle_unit(stem);
  if (unit == AngleUnit::kRad) return vector3_or(rad_key, fallback);
  if (unit == AngleUnit::kDeg) {
    const std::array<double, 3> nan3{std::nan(""), std::nan(""), std::nan("")};
    const std::array<double, 3> deg = vector3_or(deg_key, nan3);
    if (std::isnan(deg[0])) return fallback;
    return {deg[0] * std::numbers::pi / 180.0, deg[1] * std::numbers::pi / 180.0,
            deg[2] * std::numbers::pi / 180.0};
  }
  return fallback;
}

std::vector<double> MapReader::numbers(std::string_view key, Range each) {
  const auto entry = lookup(key);
  if (!entry) {
    if (valid_) record(mark_, child_path(key), "missing key (expected a list of numbers)");
    return {};
  }
  if (!entry->value.IsSequence()) {
    record(mark_of(*entry), child_path(key),
           "expected a list of numbers, found " + found(entry->value));
    return {};
  }
  std::vector<double> values;
  bool ok = true;
  for (std::size_t i = 0; i < entry->value.size(); ++i) {
    const YAML::Node item = entry->value[i];
    const auto value = parse_number(item);
    if (!value || !each.contains(*value)) {
      record(item.Mark(), child_path(key) + "[" + std::to_string(i) + "]",
             unexpected("a number", each, value.has_value(), found(item)));
      ok = false;
      continue;
    }
    values.push_back(*value);
  }
  if (!ok) return {};
  return values;
}

std::vector<std::string> MapReader::strings(std::string_view key) {
  if (valid_ && !has(key)) {
    lookup(key);
    record(mark_, child_path(key), "missing key (expected a list of names)");
    return {};
  }
  return strings_or(key, {});
}

std::vector<std::string> MapReader::strings_or(std::string_view key,
                                               std::vector<std::string> fallback) {
  const auto entry = lookup(key);
  if (!entry) return fallback;
  if (!entry->value.IsSequence()) {
    record(mark_of(*entry), child_path(key),
           "expected a list of names, found " + found(entry->value));
    return fallback;
  }
  std::vector<std::string> values;
  for (std::size_t i = 0; i < entry->value.size(); ++i) {
    const YAML::Node item = entry->value[i];
    if (!item.IsScalar() || item.Scalar().empty()) {
      record(item.Mark(), child_path(key) + "[" + std::to_string(i) + "]",
             "expected a name, found " + found(item));
      values.emplace_back();
      continue;
    }
    values.push_back(item.Scalar());
  }
  return values;
}

MapReader MapReader::map(std::string_view key) {
  auto sub = optional_map(key);
  if (sub) return std::move(*sub);
  if (valid_) record(mark_, child_path(key), "missing key (expected a map)");
  return silent(child_path(key));
}

std::optional<MapReader> MapReader::optional_map(std::string_view key) {
  const auto entry = lookup(key);
  if (!entry) return std::nullopt;
  return MapReader(entry->value, child_path(key), file_, issues_, mark_of(*entry));
}

std::vector<std::pair<std::string, MapReader>> MapReader::named_maps(std::string_view key) {
  std::vector<std::pair<std::string, MapReader>> entries;
  const auto entry = lookup(key);
  if (!entry || entry->value.IsNull()) return entries;
  if (!entry->value.IsMap()) {
    record(mark_of(*entry), child_path(key),
           "expected a map of entries keyed by name, found " + found(entry->value));
    return entries;
  }
  const std::string path = child_path(key);
  std::set<std::string, std::less<>> seen;
  for (auto it = entry->value.begin(); it != entry->value.end(); ++it) {
    if (!it->first.IsScalar() || it->first.Scalar().empty()) {
      record(it->first.Mark(), path, "expected a name as key, found " + found(it->first));
      continue;
    }
    const std::string& name = it->first.Scalar();
    const std::string entry_path = path + "." + name;
    if (!seen.insert(name).second) {
      record(it->first.Mark(), entry_path, "duplicate name (each entry must be named once)");
      continue;
    }
    entries.emplace_back(name, MapReader(it->second, entry_path, file_, issues_,
                                         mark_of(Entry{it->first, it->second})));
  }
  return entries;
}

std::vector<MapReader> MapReader::map_list(std::string_view key) {
  std::vector<MapReader> readers;
  const auto entry = lookup(key);
  if (!entry || entry->value.IsNull()) return readers;
  if (!entry->value.IsSequence()) {
    record(mark_of(*entry), child_path(key),
           "expected a list of maps, found " + found(entry->value));
    return readers;
  }
  for (std::size_t i = 0; i < entry->value.size(); ++i) {
    const YAML::Node item = entry->value[i];
    readers.push_back(MapReader(item, child_path(key) + "[" + std::to_string(i) + "]", file_,
                                issues_, item.IsNull() ? mark_of(*entry) : item.Mark()));
  }
  return readers;
}

std::vector<MapReader::ScalarEntry> MapReader::scalars() {
  std::vector<ScalarEntry> entries;
  if (!valid_) return entries;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (!it->first.IsScalar()) continue;  // A key that is no scalar is finish()'s to report.
    const std::string key = it->first.Scalar();
    read_keys_.emplace(key);
    const Entry entry{it->first, it->second};
    if (!it->second.IsScalar()) {
      record(mark_of(entry), child_path(key),
             "expected a number, text or true/false, found " + found(it->second));
      continue;
    }
    const YAML::Mark at = it->first.Mark();
    entries.push_back({key, it->second.Scalar(), at.is_null() || at.line < 0 ? 0 : at.line + 1});
  }
  return entries;
}

void MapReader::error(std::string_view key, std::string message) {
  if (!valid_ || key.empty()) {
    record(mark_, key_path_, std::move(message));
    return;
  }
  const auto entry = lookup(key);
  record(entry ? mark_of(*entry) : mark_, child_path(key), std::move(message));
}

void MapReader::error(std::string_view key, std::size_t index, std::string message) {
  const std::string path = child_path(key) + "[" + std::to_string(index) + "]";
  if (!valid_) {
    record(mark_, path, std::move(message));
    return;
  }
  const auto entry = lookup(key);
  YAML::Mark at = entry ? mark_of(*entry) : mark_;
  if (entry && entry->value.IsSequence() && index < entry->value.size()) {
    at = entry->value[index].Mark();
  }
  record(at, path, std::move(message));
}

void MapReader::finish() {
  if (!valid_) return;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (!it->first.IsScalar()) {
      record(it->first.Mark(), key_path_, "expected a key name, found " + found(it->first));
      continue;
    }
    const std::string& key = it->first.Scalar();
    if (read_keys_.contains(key)) continue;
    std::string message = "unknown key " + in_quotes(key);
    const std::vector<std::string> known(read_keys_.begin(), read_keys_.end());
    if (const auto suggestion = closest_name(key, known)) {
      message += "; did you mean " + in_quotes(*suggestion) + "?";
    } else {
      message += "; expected one of " + join(known);
    }
    record(it->first.Mark(), child_path(key), std::move(message));
  }
}

// ---------------------------------------------------------------------------------------------
// Overrides and suggestions

ConfigOverride parse_override(std::string_view text) {
  const auto fail = [&](std::string key_path, std::string message) {
    throw ConfigError({ConfigIssue{"--set", 0, 0, std::move(key_path), std::move(message)}});
  };
  const std::size_t equals = text.find('=');
  if (equals == std::string_view::npos) {
    fail("", "expected key.path=value, found " + in_quotes(std::string(text)) + " (no '=')");
  }
  const std::string key_path(text.substr(0, equals));
  if (key_path.empty()) {
    fail("",
         "expected key.path=value, found " + in_quotes(std::string(text)) + " (empty key path)");
  }
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key_path.find('.', start);
    const std::size_t end = dot == std::string::npos ? key_path.size() : dot;
    if (end == start) {
      fail(key_path, "expected a key path of names separated by single dots, found " +
                         in_quotes(key_path) + " (an empty name)");
    }
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return ConfigOverride{key_path, std::string(text.substr(equals + 1))};
}

}  // namespace cambio::config
