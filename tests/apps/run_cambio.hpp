#pragma once

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <string>

namespace cambio::testing {

struct CommandResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together.
};

/// Runs the built `cambio` program with `arguments` (shell syntax) from the source tree.
inline CommandResult run_cambio(const std::string& arguments) {
  const std::string command = std::string("cd '") + CAMBIO_SOURCE_DIR + "' && '" +
                              CAMBIO_BINARY_DIR + "/bin/cambio' " + arguments + " 2>&1";
  CommandResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe) != nullptr) result.output += buffer.data();
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

}  // namespace cambio::testing
