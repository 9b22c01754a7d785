#pragma once

#include <array>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "cambio/config/config_error.hpp"
#include "cambio/hal/closest_name.hpp"

namespace cambio::config {

/// Where issues found while reading one document accumulate.
class IssueList {
 public:
  /// Records `issue`; one located at or under a key set by `--set` (see mark_overridden) is
  /// re-attributed to file "--set" with no line or column, since its YAML marks point into the
  /// override's text rather than the file.
  void add(ConfigIssue issue);
  /// `issue` as add() would record it (an overridden key's location is "--set").
  ConfigIssue located(ConfigIssue issue) const;
  /// Declares that `key_path` (and everything under it) came from a `--set` override.
  void mark_overridden(std::string key_path);
  /// Declares that a `--set` created the map at `key_path`, which the file does not have (the
  /// typo joints.neck_pam of `--set joints.neck_pam.max_velocity_rad_s=3`); `file_keys` are the
  /// keys the file has beside it. The keys then missing under it are reported as one issue at
  /// `key_path`, with a "did you mean" among `file_keys`, instead of one "missing key" each.
  void mark_created(std::string key_path, std::vector<std::string> file_keys);
  bool empty() const { return issues_.empty(); }
  const std::vector<ConfigIssue>& issues() const { return issues_; }
  /// Throws ConfigError with every issue, ordered by file, line and column, if there is any.
  void throw_if_any() const;

 private:
  struct CreatedMap {
    std::string key_path;
    std::vector<std::string> file_keys;
  };
  std::vector<ConfigIssue> issues_;
  std::vector<std::string> overridden_paths_;
  std::vector<CreatedMap> created_maps_;
};

/// Inclusive or exclusive bounds on a number.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
  bool max_exclusive = false;
  /// Why the bounds are what they are, for a bound that is not self-evident (a size the program
  /// allocates, a hardware limit); the message of a value outside them ends with it. Must
  /// outlive the Range (a string literal or a constant).
  std::string_view reason{};

  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range non_negative() {
    return {0.0, std::numeric_limits<double>::infinity(), false, false};
  }
  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  /// This range with `why` as its reason.
  Range because(std::string_view why) const {
    Range range = *this;
    range.reason = why;
    return range;
  }
  bool contains(double value) const;
  std::string describe() const;  ///< e.g. "> 0", "in [1, 127]".
};

/// Reads one YAML map with validation. Accessors never throw on bad input: they record an
/// issue (file, line, column, key path, expected vs found) in the shared IssueList and return
/// the fallback, so a whole file is checked in one pass. Call finish() once all keys were read:
/// it reports keys nobody asked for, with a "did you mean" suggestion.
///
/// Keys carry units: number("max_velocity_rad_s"). angle_rad("min_position") accepts either
/// "min_position_rad" or "min_position_deg" (converted at load) and refuses both at once.
///
/// Locations are 1-based. A wrong value is reported at the value, an unknown or repeated key at
/// the key, and a missing key at the map that should hold it (a block map's first key, a flow
/// map's '{'). Quoted scalars are text: "2.0" in quotes is not a number.
class MapReader {
 public:
  /// `node` must be a map (an issue is recorded otherwise and every read returns fallbacks).
  MapReader(YAML::Node node, std::string key_path, std::string file,
            std::shared_ptr<IssueList> issues);

  bool has(std::string_view key) const;
  /// Whether `key` holds a list (for a key that takes a name or a list of numbers).
  bool is_list(std::string_view key) const;
  /// Whether `key` holds a map (for a key that takes a word or a map: `homing: none`).
  bool is_map(std::string_view key) const;

  double number(std::string_view key, Range range = {});
  double number_or(std::string_view key, double fallback, Range range = {});
  std::int64_t integer(std::string_view key, Range range = {});
  std::int64_t integer_or(std::string_view key, std::int64_t fallback, Range range = {});
  bool boolean(std::string_view key);
  bool boolean_or(std::string_view key, bool fallback);
  std::string text(std::string_view key);
  std::string text_or(std::string_view key, std::string fallback);
  /// A string that must be one of `allowed`; the issue lists them.
  std::string choice(std::string_view key, std::initializer_list<std::string_view> allowed);
  std::string choice_or(std::string_view key, std::initializer_list<std::string_view> allowed,
                        std::string fallback);
  /// Reads `<stem>_rad` or `<stem>_deg` (degrees converted to radians); `range_rad` in radians.
  double angle_rad(std::string_view stem, Range range_rad = {});
  double angle_rad_or(std::string_view stem, double fallback_rad, Range range_rad = {});
  std::array<double, 3> vector3(std::string_view key, Range each = {});
  std::array<double, 3> vector3_or(std::string_view key, std::array<double, 3> fallback,
                                   Range each = {});
  /// Reads `<stem>_rad` or `<stem>_deg` as three angles (roll, pitch, yaw).
  std::array<double, 3> angles3_rad_or(std::string_view stem, std::array<double, 3> fallback);
  std::vector<double> numbers(std::string_view key, Range each = {});
  std::vector<std::string> strings(std::string_view key);
  std::vector<std::string> strings_or(std::string_view key, std::vector<std::string> fallback);

  /// A required sub-map.
  MapReader map(std::string_view key);
  /// An optional sub-map: nullopt when the key is absent.
  std::optional<MapReader> optional_map(std::string_view key);
  /// The entries of a map keyed by name (`joints: {neck_pan: {...}, ...}`), in file order.
  /// Each value must be a map. An absent or empty key gives no entries and no issue (the caller
  /// decides whether the section is required).
  std::vector<std::pair<std::string, MapReader>> named_maps(std::string_view key);
  /// A list of maps (`objects: [{...}, ...]`), each located at its own line.
  std::vector<MapReader> map_list(std::string_view key);
  /// One entry of a map whose keys the reader does not know (a user behaviour's parameters).
  struct ScalarEntry {
    std::string key;
    std::string text;  ///< The scalar as written.
    int line = 0;      ///< 1-based; 0 when unknown.
  };
  /// Every entry of this map, in file order, each marked as read; a value that is not a scalar
  /// (a list, a map, nothing) is reported at its key and left out.
  std::vector<ScalarEntry> scalars();

  /// Records an issue located at `key` (or at this map if the key is absent or empty): for
  /// consistency checks that span several keys, e.g. "min_position_rad (1.2) is above
  /// max_position_rad (0.5)".
  void error(std::string_view key, std::string message);
  /// Records an issue located at item `index` of the list under `key` (key path "key[index]"),
  /// e.g. an unknown joint named in a group's joint list.
  void error(std::string_view key, std::size_t index, std::string message);
  /// Reports unknown keys (with a "did you mean"). Call after every key was read.
  void finish();

  const std::string& key_path() const { return key_path_; }
  const std::string& file() const { return file_; }
  std::string child_path(std::string_view key) const;
  /// Where `key` of this map is (its value; the map itself when absent), as an issue with no
  /// message: for a check made later, by a layer that knows what the loader cannot (which
  /// backends this build carries). Marks nothing as read.
  ConfigIssue location_of(std::string_view key) const;
  /// Records where this map and each of its keys are, by key path, into `index`.
  void record_locations(std::map<std::string, ConfigIssue, std::less<>>& index) const;
  const std::shared_ptr<IssueList>& issues() const { return issues_; }

 private:
  struct Entry {
    YAML::Node key;
    YAML::Node value;
  };
  /// `mark` locates this map in messages (a null value's own mark is unhelpful, so a map read
  /// from `key: <nothing>` is located at its key).
  MapReader(YAML::Node node, std::string key_path, std::string file,
            std::shared_ptr<IssueList> issues, YAML::Mark mark);
  /// Finds `key` and marks it as read; nullopt when absent.
  std::optional<Entry> lookup(std::string_view key);
  /// Which of `<stem>_rad` and `<stem>_deg` this map holds; both at once is recorded as an
  /// issue (at the later key) and reported as kBoth.
  enum class AngleUnit { kAbsent, kRad, kDeg, kBoth };
  AngleUnit angle_unit(std::string_view stem);
  /// Where an issue about `entry` is located: its value, or its key when the value is empty.
  static YAML::Mark mark_of(const Entry& entry);
  void record(const YAML::Mark& at, std::string key_path, std::string message);
  /// A reader that reports nothing and returns fallbacks (for a map that is missing or wrong,
  /// already reported once).
  MapReader silent(std::string key_path) const;

  YAML::Node node_;
  YAML::Mark mark_;
  std::string key_path_;
  std::string file_;
  std::shared_ptr<IssueList> issues_;
  std::set<std::string, std::less<>> read_keys_;
  bool valid_ = true;
};

/// The largest config file read, and YAML text parsed: 1 MiB. The shipped files hold at most
/// 10 KiB and a scene of 1000 objects (the most one may hold) about 300 KiB; yaml-cpp takes up to
/// ~300 bytes of memory per byte of YAML (measured: 1 MiB of "[0,0,...]" takes 290 MB), so this
/// bounds what parsing a config can take.
inline constexpr std::size_t kMaxConfigFileBytes = std::size_t{1} << 20;

/// The largest `--set` value (a number, a list, a map of a few keys): 64 KiB.
inline constexpr std::size_t kMaxOverrideValueBytes = std::size_t{64} << 10;

/// Why `path` cannot be read as a config file, as the end of a message: "it does not exist",
/// "permission denied", "it is a directory, expected a YAML file", "it is a character device
/// (such as /dev/zero), expected a regular file", "it holds 5000000 bytes, ...". nullopt when it
/// is a regular file of at most kMaxConfigFileBytes this process may read. Opens only regular
/// files (opening a device can act on it). Never throws.
std::optional<std::string> config_file_problem(const std::string& path);

/// As config_file_problem() for a file of any size that is not read as a config (a plugin's
/// shared library).
std::optional<std::string> readable_file_problem(const std::string& path);

/// A `--set key.path=value` override from the command line.
struct ConfigOverride {
  std::string key_path;
  std::string value;  ///< Parsed as a YAML scalar or flow sequence/map ("[1, 2]").
};

/// Parses "key.path=value"; throws ConfigError (file "--set") if malformed.
ConfigOverride parse_override(std::string_view text);

/// A YAML document loaded from a file (or a string), with overrides applied on top before
/// anything reads it. Overridden values are reported with file "--set".
class ConfigDocument {
 public:
  /// Throws ConfigError when the file cannot be read as a config (see config_file_problem), or
  /// does not hold exactly one YAML document (a syntax error is reported with its line).
  static ConfigDocument load_file(const std::string& path,
                                  const std::vector<ConfigOverride>& overrides = {});
  /// The same from `text` (at most kMaxConfigFileBytes); `name` stands for the file in messages.
  static ConfigDocument from_string(const std::string& text, const std::string& name,
                                    const std::vector<ConfigOverride>& overrides = {});

  /// The top-level map, reading into this document's IssueList.
  MapReader root();
  const std::string& file() const { return file_; }
  const std::shared_ptr<IssueList>& issues() const { return issues_; }

 private:
  ConfigDocument(YAML::Node root, std::string file);
  static ConfigDocument parse(const std::string& text, const std::string& name,
                              const std::vector<ConfigOverride>& overrides);
  /// Sets the override's key in the tree, creating missing maps (see IssueList::mark_created);
  /// records an issue (file "--set") when the value is not one YAML value of at most
  /// kMaxOverrideValueBytes, or the path runs through a non-map or past a list's end.
  void apply(const ConfigOverride& override_value);
  YAML::Node root_;
  std::string file_;
  std::shared_ptr<IssueList> issues_;
};

/// The "did you mean" of every refused name (cambio/hal/closest_name.hpp).
using hal::closest_name;
using hal::edit_distance;

}  // namespace cambio::config
