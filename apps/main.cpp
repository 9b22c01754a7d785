// `cambio`: the command-line front end. Dispatches to one subcommand per file.
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "argument_parser.hpp"
#include "command.hpp"

namespace {

void print_usage(std::ostream& out) {
  out << "usage: cambio <command> [options]\n\nCâmbio: real-time control stack for active-vision "
         "robots.\n\ncommands:\n";
  for (const auto& command : cambio::app::all_commands()) {
    out << "  " << command.name
        << std::string(20 - std::min<std::size_t>(19, command.name.size()), ' ') << command.summary
        << "\n";
  }
  out << "\n'cambio <command> --help' describes a command.\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    print_usage(std::cerr);
    return cambio::app::kExitBadInput;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    print_usage(std::cout);
    return cambio::app::kExitOk;
  }
  const std::vector<std::string> args(argv + 2, argv + argc);
  for (const auto& command : cambio::app::all_commands()) {
    if (command.name != name) continue;
    try {
      return command.run(args);
    } catch (const cambio::app::UsageError& error) {
      std::cerr << "cambio " << error.what() << "\n";
      return cambio::app::kExitBadInput;
    } catch (const std::exception& error) {
      std::cerr << "cambio " << name << ": error: " << error.what() << "\n";
      return cambio::app::kExitFailure;
    }
  }
  std::cerr << "cambio: unknown command '" << name << "'\n\n";
  print_usage(std::cerr);
  return cambio::app::kExitBadInput;
}
