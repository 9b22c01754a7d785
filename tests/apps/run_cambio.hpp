#pragma once

#include <sys/wait.h>
#include <array>
#include <cstdint>
#include <cstdio>
#include <string>

namespace cambio::testing {

struct CommandResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together, or stdout alone (Capture::kStdout).
};

enum class Capture : std::uint8_t {
  kStdoutAndStderr,
  kStdout,  ///< For output that is parsed (JSON); stderr goes to the test's own.
};

/// Runs a shell command line and captures its standard output.
inline CommandResult run_shell(const std::string& command) {
  CommandResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe) != nullptr) result.output += buffer.data();
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

/// Runs the built `cambio` program with `arguments` (shell syntax) from the source tree.
inline CommandResult run_cambio(const std::string& arguments,
                                Capture capture = Capture::kStdoutAndStderr) {
  return run_shell(std::string("cd '") + CAMBIO_SOURCE_DIR + "' && '" + CAMBIO_BINARY_DIR +
                   "/bin/cambio' " + arguments +
                   (capture == Capture::kStdoutAndStderr ? " 2>&1" : ""));
}

}  // namespace cambio::testing
