#pragma once

#include <span>
#include <string>
#include <string_view>

namespace cambio::app {

/// Exit statuses, one table for the whole program (`cambio --help` prints it). Where several
/// apply: a signal over a device fault over a failed goal.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;      ///< The job ran and an experiment's goal failed.
inline constexpr int kExitBadInput = 2;     ///< Bad arguments, config, input or output files.
inline constexpr int kExitDeviceFault = 3;  ///< A device (drive, bus) fault stopped the run.
// 130 / 143: stopped by SIGINT / SIGTERM (SIGHUP counts as SIGTERM); see stop_signal.hpp.

/// One `cambio <name>` subcommand. `args` excludes the program and subcommand names.
struct Command {
  std::string_view name;
  std::string_view summary;
  int (*run)(std::span<const std::string> args);
};

/// Every subcommand, in the order `cambio --help` lists them (command_table.cpp).
std::span<const Command> all_commands();

}  // namespace cambio::app
