#pragma once

// What the commands' JSON outputs (perceive's result.json, the -bench commands' --json) share.
// The documents are nlohmann::ordered_json, so keys print in the order the code lists them.

#include <string>

#include <nlohmann/json.hpp>

namespace cambio::app {

using Json = nlohmann::ordered_json;

/// `value` as printf's `format` shows it ("%.1f", "%.6g"): a figure keeps the precision it is
/// meaningful to, and the JSON shows those digits (nlohmann::json writes the shortest text that
/// reads back the same double). Non-finite values stay so and are written as null.
double as_printed(double value, const char* format);

/// `json` as text, two-space indented, ending in a newline. Text that is not UTF-8 (a path in
/// another encoding) is written with U+FFFD in place of the bad bytes instead of throwing.
std::string json_text(const Json& json);

}  // namespace cambio::app
