#include "json_output.hpp"

#include <cstdio>
#include <cstdlib>

namespace cambio::app {

double as_printed(double value, const char* format) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return std::strtod(text, nullptr);
}

std::string json_text(const Json& json) {
  return json.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

}  // namespace cambio::app
