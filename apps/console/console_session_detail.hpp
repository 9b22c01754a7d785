#pragma once

// What the console session's source files share (console_session.cpp: a line carried out and the
// loops' refusals; console_session_aim.cpp: look and saccade targets; console_session_status.cpp:
// `status`; console_session_ssm.cpp: `ssm`). Not installed.

#include <cstdio>
#include <numbers>
#include <string>

namespace cambio::app::console::detail {

/// printf into a string; every line the console prints fits in 256 characters.
inline std::string format(const char* pattern, auto... values) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, values...);
  return text;
}

inline double degrees(double rad) {
  return rad * 180.0 / std::numbers::pi;
}

}  // namespace cambio::app::console::detail
