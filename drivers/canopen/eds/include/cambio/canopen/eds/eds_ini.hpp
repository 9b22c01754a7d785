#pragma once

// The INI layer of CiA 306 (§4.1): [sections] of key=value lines, ';' starting a comment line.
// Section names and keys are case-insensitive; spaces around '=' and keys, CRLF line ends and
// a UTF-8 byte order mark are tolerated. Every line that is none of these is an issue; a duplicate
// section or key is one too (the first is kept). Never throws on bad input, reads only within
// the text it is given.

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/canopen/eds/eds_issue.hpp"

namespace cambio::canopen::eds {

struct IniKey {
  std::string name;  ///< Lower case.
  std::string value;
  int line = 0;
};

struct IniSection {
  std::string name;  ///< As written (trimmed).
  std::string lower_name;
  int line = 0;
  std::vector<IniKey> keys;

  /// The key `lower_name` (lower case), or nullptr.
  const IniKey* find(std::string_view lower_key) const;
};

struct IniDocument {
  std::vector<IniSection> sections;                         ///< In file order.
  std::map<std::string, std::size_t, std::less<>> by_name;  ///< Lower-case name -> position.

  const IniSection* find(std::string_view lower_name) const;
};

/// Reads `text`; problems go to `issues`, located in `file`.
IniDocument read_ini(std::string_view text, const std::string& file, std::vector<EdsIssue>& issues);

/// `text` in lower case (ASCII).
std::string lower_case(std::string_view text);

}  // namespace cambio::canopen::eds
