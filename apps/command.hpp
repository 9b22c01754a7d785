#pragma once

#include <span>
#include <string>
#include <string_view>

namespace cambio::app {

/// Exit codes shared by every subcommand.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;   ///< The job ran and failed (or a goal was missed).
inline constexpr int kExitBadInput = 2;  ///< Bad arguments, config, or input files.

/// One `cambio <name>` subcommand. `args` excludes the program and subcommand names.
struct Command {
  std::string_view name;
  std::string_view summary;
  int (*run)(std::span<const std::string> args);
};

/// Every subcommand, in the order `cambio --help` lists them (command_table.cpp).
std::span<const Command> all_commands();

}  // namespace cambio::app
