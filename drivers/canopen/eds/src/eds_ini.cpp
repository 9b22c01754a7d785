#include "cambio/canopen/eds/eds_ini.hpp"

#include <cctype>

#include "cambio/canopen/eds/eds_value.hpp"

namespace cambio::canopen::eds {

namespace {

/// A line as a message quotes it: at most 60 characters.
std::string in_quotes(std::string_view text) {
  constexpr std::size_t kShown = 60;
  return "'" + std::string(text.substr(0, kShown)) + (text.size() > kShown ? "...'" : "'");
}

}  // namespace

std::string lower_case(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

const IniKey* IniSection::find(std::string_view lower_key) const {
  for (const IniKey& key : keys) {
    if (key.name == lower_key) return &key;
  }
  return nullptr;
}

const IniSection* IniDocument::find(std::string_view lower_name) const {
  const auto it = by_name.find(lower_name);
  return it == by_name.end() ? nullptr : &sections[it->second];
}

IniDocument read_ini(std::string_view text, const std::string& file,
                     std::vector<EdsIssue>& issues) {
  constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
  if (text.substr(0, kByteOrderMark.size()) == kByteOrderMark) {
    text.remove_prefix(kByteOrderMark.size());
  }
  IniDocument document;
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::size_t current = kNone;  // An index: the vector grows.
  bool current_is_duplicate = false;
  int line_number = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = trim(text.substr(start, end - start));  // '\r' is a space.
    start = end + 1;
    ++line_number;
    if (line.empty() || line.front() == ';') continue;
    if (line.front() == '[') {
      const std::size_t close = line.find(']');
      if (close == std::string_view::npos || !trim(line.substr(close + 1)).empty()) {
        issues.push_back(
            {file, line_number, "expected a section header '[name]', found " + in_quotes(line)});
        current = kNone;
        current_is_duplicate = true;  // Its keys belong to no section: not reported again.
        continue;
      }
      const std::string_view name = trim(line.substr(1, close - 1));
      std::string lower = lower_case(name);
      if (const IniSection* first = document.find(lower)) {
        issues.push_back({file, line_number,
                          "duplicate section [" + std::string(name) + "] (first at line " +
                              std::to_string(first->line) + "); this one is ignored"});
        current = kNone;
        current_is_duplicate = true;
        continue;
      }
      document.by_name.emplace(lower, document.sections.size());
      document.sections.push_back({std::string(name), std::move(lower), line_number, {}});
      current = document.sections.size() - 1;
      current_is_duplicate = false;
      continue;
    }
    const std::size_t equals = line.find('=');
    if (equals == std::string_view::npos || trim(line.substr(0, equals)).empty()) {
      issues.push_back(
          {file, line_number,
           "expected 'key=value', a '[section]' or a ';' comment, found " + in_quotes(line)});
      continue;
    }
    if (current == kNone) {
      if (!current_is_duplicate) {
        issues.push_back({file, line_number, "key before any [section]: " + in_quotes(line)});
      }
      continue;
    }
    IniKey key{lower_case(trim(line.substr(0, equals))), std::string(trim(line.substr(equals + 1))),
               line_number};
    IniSection& section = document.sections[current];
    if (const IniKey* first = section.find(key.name)) {
      issues.push_back({file, line_number,
                        "[" + section.name + "]: duplicate key " +
                            std::string(trim(line.substr(0, equals))) + " (first at line " +
                            std::to_string(first->line) + ")"});
      continue;
    }
    section.keys.push_back(std::move(key));
  }
  return document;
}

}  // namespace cambio::canopen::eds
