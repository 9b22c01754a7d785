#pragma once

// What the console's parser shares with its command table (console_line.cpp: words into a
// Command; console_syntax.cpp: the commands' names, usage and help). Not installed.

#include <string>
#include <string_view>
#include <vector>

namespace cambio::app::console::detail {

/// One command as `help` and the parser's messages show it.
struct Syntax {
  const char* name;
  const char* usage;
  const char* what;
};

/// The command named `name`, or nullptr.
const Syntax* find_syntax(std::string_view name);

/// Every command's name, for "did you mean".
std::vector<std::string> command_names();

}  // namespace cambio::app::console::detail
