#pragma once

#include <string>

namespace cambio::canopen::eds {

/// One malformed thing in an EDS, located at its line.
struct EdsIssue {
  std::string file;
  int line = 0;  ///< 1-based; 0 when the file as a whole is meant (unreadable).
  std::string message;

  /// "file:line: message" (the form compilers use, so editors can jump).
  std::string to_string() const {
    return file + ":" + (line > 0 ? std::to_string(line) + ":" : std::string()) + " " + message;
  }
};

}  // namespace cambio::canopen::eds
