#pragma once

#include <map>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/config/map_reader.hpp"

namespace cambio::app {

/// A command-line mistake; the message names the option and what was wrong.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A small, strict parser for `--name value`, `--name=value`, `--flag` and positionals.
/// Unknown options, missing values and malformed numbers throw UsageError. Options declared
/// repeatable (like --set) collect every occurrence. Numbers are read only with a range and the
/// reason for it, as config values are (config::Range), so no option takes a value the code
/// behind it cannot use.
class ArgumentParser {
 public:
  ArgumentParser(std::string command, std::string synopsis);

  ArgumentParser& option(std::string name, std::string value_name, std::string help);
  ArgumentParser& repeated_option(std::string name, std::string value_name, std::string help);
  ArgumentParser& flag(std::string name, std::string help);
  ArgumentParser& positional(std::string name, std::string help, bool required = true);

  /// Returns false when --help was given (the help text is then already printed to stdout).
  bool parse(std::span<const std::string> args);

  bool has(std::string_view name) const;
  bool flag_set(std::string_view name) const { return has(name); }
  std::string value(std::string_view name, std::string fallback = {}) const;
  std::vector<std::string> values(std::string_view name) const;
  /// The option's value as a finite number inside `range`, or `fallback` when absent. Throws
  /// UsageError naming the option, the range, `why` (the reason for the range, shown to the
  /// user) and what was found.
  double number(std::string_view name, double fallback, const config::Range& range,
                std::string_view why) const;
  /// The same for a whole number (decimal digits, optional sign); the range must fit `long long`.
  long long integer(std::string_view name, long long fallback, const config::Range& range,
                    std::string_view why) const;
  std::optional<std::string> positional_value(std::string_view name) const;

  std::string help_text() const;

 private:
  struct Spec {
    std::string name;
    std::string value_name;  // Empty for flags.
    std::string help;
    bool repeated = false;
  };
  struct PositionalSpec {
    std::string name;
    std::string help;
    bool required = true;
  };
  const Spec* find(std::string_view name) const;
  [[noreturn]] void out_of_range(std::string_view name, std::string_view kind,
                                 const config::Range& range, std::string_view why,
                                 const std::string& found) const;

  std::string command_;
  std::string synopsis_;
  std::vector<Spec> specs_;
  std::vector<PositionalSpec> positional_specs_;
  std::map<std::string, std::vector<std::string>, std::less<>> values_;
  std::map<std::string, std::string, std::less<>> positionals_;
};

}  // namespace cambio::app
