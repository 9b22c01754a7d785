#pragma once

#include <map>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace cambio::app {

/// A command-line mistake; the message names the option and what was wrong.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A small, strict parser for `--name value`, `--name=value`, `--flag` and positionals.
/// Unknown options, missing values and malformed numbers throw UsageError. Options declared
/// repeatable (like --set) collect every occurrence.
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
  double number(std::string_view name, double fallback) const;
  long long integer(std::string_view name, long long fallback) const;
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

  std::string command_;
  std::string synopsis_;
  std::vector<Spec> specs_;
  std::vector<PositionalSpec> positional_specs_;
  std::map<std::string, std::vector<std::string>, std::less<>> values_;
  std::map<std::string, std::string, std::less<>> positionals_;
};

}  // namespace cambio::app
