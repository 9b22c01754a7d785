#include "argument_parser.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>

namespace cambio::app {

ArgumentParser::ArgumentParser(std::string command, std::string synopsis)
    : command_(std::move(command)), synopsis_(std::move(synopsis)) {}

ArgumentParser& ArgumentParser::option(std::string name, std::string value_name, std::string help) {
  specs_.push_back({std::move(name), std::move(value_name), std::move(help), false});
  return *this;
}

ArgumentParser& ArgumentParser::repeated_option(std::string name, std::string value_name,
                                                std::string help) {
  specs_.push_back({std::move(name), std::move(value_name), std::move(help), true});
  return *this;
}

ArgumentParser& ArgumentParser::flag(std::string name, std::string help) {
  specs_.push_back({std::move(name), "", std::move(help), false});
  return *this;
}

ArgumentParser& ArgumentParser::positional(std::string name, std::string help, bool required) {
  positional_specs_.push_back({std::move(name), std::move(help), required});
  return *this;
}

const ArgumentParser::Spec* ArgumentParser::find(std::string_view name) const {
  for (const auto& spec : specs_) {
    if (spec.name == name) return &spec;
  }
  return nullptr;
}

bool ArgumentParser::parse(std::span<const std::string> args) {
  std::size_t next_positional = 0;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << help_text();
      return false;
    }
    if (arg.size() > 2 && arg.starts_with("--")) {
      std::string name = arg.substr(2);
      std::optional<std::string> inline_value;
      if (const auto eq = name.find('='); eq != std::string::npos) {
        inline_value = name.substr(eq + 1);
        name.resize(eq);
      }
      const Spec* spec = find(name);
      if (spec == nullptr) {
        throw UsageError(command_ + ": unknown option '--" + name + "' (see 'cambio " + command_ +
                         " --help')");
      }
      if (spec->value_name.empty()) {
        if (inline_value) throw UsageError(command_ + ": option '--" + name + "' takes no value");
        values_[name].push_back("");
        continue;
      }
      std::string value;
      if (inline_value) {
        value = *inline_value;
      } else {
        if (i + 1 >= args.size()) {
          throw UsageError(command_ + ": option '--" + name + "' needs a value (" +
                           spec->value_name + ")");
        }
        value = args[++i];
      }
      auto& slot = values_[name];
      if (!spec->repeated && !slot.empty()) {
        throw UsageError(command_ + ": option '--" + name + "' given more than once");
      }
      slot.push_back(value);
      continue;
    }
    if (next_positional >= positional_specs_.size()) {
      throw UsageError(command_ + ": unexpected argument '" + arg + "' (see 'cambio " + command_ +
                       " --help')");
    }
    positionals_[positional_specs_[next_positional++].name] = arg;
  }
  for (std::size_t p = next_positional; p < positional_specs_.size(); ++p) {
    if (positional_specs_[p].required) {
      throw UsageError(command_ + ": missing argument " + positional_specs_[p].name +
                       " (see 'cambio " + command_ + " --help')");
    }
  }
  return true;
}

bool ArgumentParser::has(std::string_view name) const {
  const auto it = values_.find(name);
  return it != values_.end() && !it->second.empty();
}

std::string ArgumentParser::value(std::string_view name, std::string fallback) const {
  const auto it = values_.find(name);
  return it == values_.end() || it->second.empty() ? fallback : it->second.back();
}

std::vector<std::string> ArgumentParser::values(std::string_view name) const {
  const auto it = values_.find(name);
  return it == values_.end() ? std::vector<std::string>{} : it->second;
}

void ArgumentParser::out_of_range(std::string_view name, std::string_view kind,
                                  const config::Range& range, std::string_view why,
                                  const std::string& found) const {
  const std::string bounds = range.describe();
  throw UsageError(command_ + ": option '--" + std::string(name) + "' expects " +
                   std::string(kind) + (bounds.empty() ? "" : " " + bounds) + " (" +
                   std::string(why) + "), got '" + found + "'");
}

double ArgumentParser::number(std::string_view name, double fallback, const config::Range& range,
                              std::string_view why) const {
  if (!has(name)) return fallback;
  const std::string text = value(name);
  char* end = nullptr;
  errno = 0;
  const double parsed = std::strtod(text.c_str(), &end);
  // strtod also reads "inf", "nan", hexadecimal and leading blanks; only decimal text passes.
  const bool decimal = std::all_of(text.begin(), text.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) != 0 || c == '+' || c == '-' || c == '.' ||
           c == 'e' || c == 'E';
  });
  if (text.empty() || !decimal || end != text.c_str() + text.size() || errno != 0 ||
      !std::isfinite(parsed) || !range.contains(parsed)) {
    out_of_range(name, "a number", range, why, text);
  }
  return parsed;
}

long long ArgumentParser::integer(std::string_view name, long long fallback,
                                  const config::Range& range, std::string_view why) const {
  if (!has(name)) return fallback;
  const std::string text = value(name);
  char* end = nullptr;
  errno = 0;
  const long long parsed = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front())) != 0 ||
      end != text.c_str() + text.size() || errno != 0 ||
      !range.contains(static_cast<double>(parsed))) {
    out_of_range(name, "a whole number", range, why, text);
  }
  return parsed;
}

std::optional<std::string> ArgumentParser::positional_value(std::string_view name) const {
  const auto it = positionals_.find(name);
  if (it == positionals_.end()) return std::nullopt;
  return it->second;
}

std::string ArgumentParser::help_text() const {
  std::string text = "usage: cambio " + command_ + " " + synopsis_ + "\n";
  if (!positional_specs_.empty()) {
    text += "\narguments:\n";
    for (const auto& p : positional_specs_) text += "  " + p.name + "\n      " + p.help + "\n";
  }
  text += "\noptions:\n";
  for (const auto& spec : specs_) {
    text += "  --" + spec.name + (spec.value_name.empty() ? "" : " " + spec.value_name) +
            (spec.repeated ? " (repeatable)" : "") + "\n      " + spec.help + "\n";
  }
  text += "  --help\n      show this help and exit\n";
  return text;
}

}  // namespace cambio::app
