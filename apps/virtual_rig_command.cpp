// `cambio virtual-rig --config RIG [--set key=value]... [--fault SPEC]... [--fault-file FILE]
// [--seed N] [--duration-s S]`: emulates one CiA 402 drive per CAN joint of the rig on the
// interfaces its can_buses name, until SIGINT/SIGTERM or the duration. The emulation is in
// runs/virtual_rig_run.hpp.
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "argument_parser.hpp"
#include "bounded_line.hpp"
#include "cambio/canopen/can_rig_check.hpp"
#include "cambio/canopen/can_rig_from_config.hpp"
#include "cambio/canopen/socketcan_backend.hpp"
#include "cambio/config/echoed_text.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/shipped_config.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "virtual_rig_run.hpp"

namespace cambio::app {

namespace {

/// Fault specifications from a file, one per line; blank lines and # comments are skipped.
std::vector<virtual_rig::FaultInjection> read_fault_file(const std::string& path) {
  // A directory, a FIFO or a device (/dev/zero) is no list of faults.
  std::error_code status_error;
  if (!std::filesystem::is_regular_file(path, status_error)) {
    throw UsageError("virtual-rig: --fault-file " + config::echoed(path) +
                     ": not a regular file (a list of fault specifications, one per line)");
  }
  std::ifstream in(path);
  if (!in)
    throw UsageError("virtual-rig: --fault-file " + config::echoed(path) + ": cannot be read");
  std::vector<virtual_rig::FaultInjection> faults;
  std::string line;
  for (int number = 1;; ++number) {
    const LineRead got = read_bounded_line(in, line);
    if (got == LineRead::kEnd) break;
    if (got == LineRead::kTooLong) {
      throw UsageError("virtual-rig: " + config::echoed(path) + ":" + std::to_string(number) +
                       ": longer than " + std::to_string(kMaxInputLineChars) +
                       " characters: not a fault specification");
    }
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    const std::size_t last = line.find_last_not_of(" \t\r");
    try {
      faults.push_back(virtual_rig::parse_fault(line.substr(first, last - first + 1)));
    } catch (const std::invalid_argument& error) {
      throw UsageError("virtual-rig: " + config::echoed(path) + ":" + std::to_string(number) +
                       ": " + error.what());
    }
  }
  return faults;
}

/// The seed and the faults of --fault, then those of --fault-file.
virtual_rig::VirtualRigOptions emulation_options(const ArgumentParser& parser, long long seed) {
  virtual_rig::VirtualRigOptions options;
  options.seed = static_cast<std::uint64_t>(seed);
  for (const auto& spec : parser.values("fault")) {
    try {
      options.faults.push_back(virtual_rig::parse_fault(spec));
    } catch (const std::invalid_argument& error) {
      throw UsageError("virtual-rig: --fault " + std::string(error.what()));
    }
  }
  if (parser.has("fault-file")) {
    for (auto& fault : read_fault_file(parser.value("fault-file"))) options.faults.push_back(fault);
  }
  return options;
}

/// The rig with the --set overrides; nullopt (the issues printed) when it is invalid or its
/// CANopen side is not one a master would drive.
std::optional<config::RigConfig> load_checked_rig_or_report(const ArgumentParser& parser) {
  std::vector<config::ConfigOverride> overrides;
  try {
    for (const auto& text : parser.values("set")) overrides.push_back(config::parse_override(text));
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return std::nullopt;
  }
  auto rig = load_rig_or_report(config::resolve_config_argument("rigs", parser.value("config")),
                                overrides);
  if (!rig) return std::nullopt;
  // The rig's CANopen side as the master checks it (buses defined, node ids unique per bus), each
  // problem at its key: the drives emulated are those a master would drive.
  std::vector<config::ConfigIssue> issues;
  for (auto& problem : canopen::check_can_rig(config::hardware_description(*rig),
                                              canopen::can_rig_from_config(*rig),
                                              canopen::SocketCanBackend::kName)) {
    issues.push_back(rig->locate(problem.key_path, std::move(problem.message)));
  }
  if (!issues.empty()) {
    report_config_error(config::ConfigError(std::move(issues)));
    return std::nullopt;
  }
  return rig;
}

}  // namespace

int run_virtual_rig_command(std::span<const std::string> args) {
  ArgumentParser parser("virtual-rig",
                        "--config RIG [--set KEY=VALUE]... [--fault SPEC]... [--duration-s S]");
  parser.option("config", "RIG", "rig file or shipped rig name, e.g. pan_tilt")
      .repeated_option("set", "KEY=VALUE",
                       "override a rig key, e.g. --set can_buses.can0.interface=vcan0")
      .repeated_option("fault", "SPEC",
                       "inject a fault: KIND[,key=value]..., KIND one of heartbeat-stop, emcy, "
                       "following-error, error-frames, drop-tpdo, late-tpdo, sdo-abort; keys "
                       "node, at_s, code, fault, count, delay_ms, object; e.g. "
                       "emcy,node=1,at_s=2,code=0x7300")
      .option("fault-file", "FILE", "fault specifications, one per line (# comments)")
      .option("seed", "N", "seed of the servos' motion noise (default 1)")
      .option("duration-s", "S", "stop after S seconds (default: until SIGINT/SIGTERM)");
  if (!parser.parse(args)) return kExitOk;
  if (!parser.has("config")) throw UsageError("virtual-rig: --config RIG is required");
  const double duration_s = parser.number("duration-s", 0.0, config::Range{0.0, 1e7, true, false},
                                          "seconds to run, up to about four months");
  const long long seed = parser.integer("seed", 1, config::Range{0.0, 9e15},
                                        "a whole number the noise generator starts from");
  const virtual_rig::VirtualRigOptions options = emulation_options(parser, seed);
  const std::optional<config::RigConfig> rig = load_checked_rig_or_report(parser);
  if (!rig) return kExitBadInput;
  return run_virtual_rig(*rig, options, duration_s);
}

}  // namespace cambio::app
