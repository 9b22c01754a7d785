#pragma once

// Helpers for the rig tests: a small valid rig with known line numbers, line patching, and
// collecting the issues a load reports.

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"

namespace cambio::config::test {

/// A valid two-joint rig. The line numbers in the comments on the right are what tests patch.
inline const std::vector<std::string> kSmallRigLines = {
    "rig:",                                                                 // 1
    "  name: test",                                                         // 2
    "joints:",                                                              // 3
    "  pan:",                                                               // 4
    "    group: head",                                                      // 5
    "    parent: base",                                                     // 6
    "    origin_xyz_m: [0.0, 0.0, 0.3]",                                    // 7
    "    axis: [0, 0, 1]",                                                  // 8
    "    min_position_deg: -90",                                            // 9
    "    max_position_deg: 90",                                             // 10
    "    max_velocity_rad_s: 2.0",                                          // 11
    "    max_acceleration_rad_s2: 20.0",                                    // 12
    "    can: {node_id: 1, gear_ratio: 50, encoder_counts_per_rev: 4096}",  // 13
    "  tilt:",                                                              // 14
    "    group: head",                                                      // 15
    "    parent: pan",                                                      // 16
    "    origin_xyz_m: [0.0, 0.0, 0.1]",                                    // 17
    "    axis: [0, 1, 0]",                                                  // 18
    "    min_position_deg: -30",                                            // 19
    "    max_position_deg: 45",                                             // 20
    "    max_velocity_rad_s: 2.0",                                          // 21
    "    max_acceleration_rad_s2: 20.0",                                    // 22
    "    can: {node_id: 2, gear_ratio: 50, encoder_counts_per_rev: 4096}",  // 23
    "groups:",                                                              // 24
    "  head: {backend: sim, joints: [pan, tilt], can_bus: can0}",           // 25
    "cameras:",                                                             // 26
    "  eye:",                                                               // 27
    "    parent: tilt",                                                     // 28
    "    width_px: 640",                                                    // 29
    "    height_px: 480",                                                   // 30
    "    focal_px: 554.256",                                                // 31
    "    principal_point_px: [319.5, 239.5]",                               // 32
    "can_buses:",                                                           // 33
    "  can0: {interface: can0, bitrate_bit_s: 1000000}",                    // 34
};

inline std::string join_lines(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& line : lines) text += line + "\n";
  return text;
}

inline std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// `lines` with 1-based line `line` replaced by `replacement` (which may hold several lines).
inline std::string patched(std::vector<std::string> lines, int line,
                           const std::string& replacement) {
  lines.at(static_cast<std::size_t>(line - 1)) = replacement;
  return join_lines(lines);
}

inline std::string small_rig() {
  return join_lines(kSmallRigLines);
}
inline std::string small_rig_with(int line, const std::string& replacement) {
  return patched(kSmallRigLines, line, replacement);
}

inline std::string shipped_rig_path(const std::string& name) {
  return find_shipped_config("rigs/" + name);
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The issues loading `yaml` reports; a test failure if it loads cleanly.
inline std::vector<ConfigIssue> issues_of(const std::string& yaml,
                                          const std::vector<ConfigOverride>& overrides = {}) {
  try {
    load_rig_from_string(yaml, "test.yaml", overrides);
  } catch (const ConfigError& error) {
    return error.issues();
  }
  ADD_FAILURE() << "expected the rig to be refused";
  return {};
}

inline std::string describe(const std::vector<ConfigIssue>& issues) {
  std::string text;
  for (const auto& issue : issues) text += "\n  " + issue.to_string();
  return text;
}

}  // namespace cambio::config::test
