// `cambio eds check VENDOR.eds --rig RIG --group G [--node-id N]`: whether a vendor's drive, as
// its EDS describes it, can drive a CAN joint group of a rig (cambio/canopen/eds/). Exits 0 when
// it fits, 1 when it does not (one line per problem), 2 for bad input (a malformed EDS, with
// file:line: for each problem; an unknown group; bad arguments).
#include <algorithm>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

#include "argument_parser.hpp"
#include "cambio/canopen/can_rig_from_config.hpp"
#include "cambio/canopen/eds/eds_file.hpp"
#include "cambio/canopen/eds/eds_group_check.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/shipped_config.hpp"
#include "command.hpp"
#include "config_errors.hpp"

namespace cambio::app {

namespace {

namespace eds = canopen::eds;

constexpr std::string_view kSubcommands = "check";

void print_report(const eds::EdsFile& file, const eds::CanGroupView& view,
                  const eds::EdsGroupReport& report, std::ostream& out) {
  const bool position =
      view.drives.empty() || view.drives.front().mode == hal::CommandMode::kPosition;
  const auto count = [](const std::optional<int>& value) {
    return value ? std::to_string(*value) : std::string("?");
  };
  out << "EDS " << file.file << ": " << file.objects.size() << " objects, "
      << "NrOfRXPDO " << count(file.rx_pdos) << ", NrOfTXPDO " << count(file.tx_pdos) << "\n";
  out << "group " << view.group.name << ": " << (position ? "CSP" : "CSV") << " at "
      << view.group.rate_hz << " Hz, heartbeat "
      << static_cast<long long>(view.settings.heartbeat_period_s * 1000.0 + 0.5) << " ms; "
      << report.joints_checked.size() << " of " << view.joints.size() << " joints checked (";
  const char* separator = "";
  for (std::size_t k = 0; k < view.joints.size(); ++k) {
    if (std::find(report.joints_checked.begin(), report.joints_checked.end(),
                  view.joints[k].name) == report.joints_checked.end()) {
      continue;
    }
    out << separator << view.joints[k].name << " node " << view.drives[k].node_id;
    separator = ", ";
  }
  out << "), " << report.objects_checked << " objects the master reads, writes or maps\n";
  for (const std::string& note : report.notes) out << "note: " << note << "\n";
  if (report.fits()) {
    out << "fits: every object the master needs is there, with a fitting size, access and "
           "limits\n";
    return;
  }
  out << "does not fit: " << report.problems.size()
      << (report.problems.size() == 1 ? " problem" : " problems") << "\n";
  for (const eds::EdsProblem& problem : report.problems) out << "  " << problem.to_string() << "\n";
}

int run_check(std::span<const std::string> args) {
  ArgumentParser parser("eds check", "VENDOR.eds --rig RIG --group G [--node-id N]");
  parser.positional("VENDOR.eds", "the drive's electronic data sheet (CiA 306)")
      .option("rig", "RIG", "rig file or shipped rig name, e.g. pan_tilt")
      .option("group", "G", "the rig's joint group the drive would drive, e.g. pan_tilt")
      .option("node-id", "N",
              "check only the group's joint on this node (default: every joint of the group)");
  if (!parser.parse(args)) return kExitOk;
  for (const char* needed : {"rig", "group"}) {
    if (!parser.has(needed)) throw UsageError(std::string("eds check: --") + needed + " is needed");
  }
  std::optional<int> node_id;
  if (parser.has("node-id")) {
    node_id = static_cast<int>(
        parser.integer("node-id", 0, config::Range::closed(1, 127), "a CANopen node id is 1..127"));
  }

  const eds::EdsReadResult eds_file = eds::read_eds_file(*parser.positional_value("VENDOR.eds"));
  if (!eds_file.ok()) {
    for (const eds::EdsIssue& issue : eds_file.issues) std::cerr << issue.to_string() << "\n";
    std::cerr << eds_file.issues.size() << (eds_file.issues.size() == 1 ? " problem" : " problems")
              << " in the EDS; nothing was checked.\n";
    return kExitBadInput;
  }
  const auto rig =
      load_rig_or_report(config::resolve_config_argument("rigs", parser.value("rig")), {});
  if (!rig) return kExitBadInput;
  try {
    const hal::HardwareInfo hardware = config::hardware_description(*rig);
    const canopen::CanRigInfo can_rig = canopen::can_rig_from_config(*rig);
    const config::LoopConfig* joint_loop = rig->find_loop("joint");
    const eds::CanGroupView view = eds::can_group_view(
        hardware, can_rig, parser.value("group"), joint_loop != nullptr ? joint_loop->rate_hz : 0);
    const eds::EdsGroupReport report = eds::check_eds_for_group(eds_file.eds, view, node_id);
    if (report.joints_checked.empty()) {
      std::cerr << "cambio eds check: no joint of group " << view.group.name << " is on node "
                << *node_id << "\n";
      return kExitBadInput;
    }
    print_report(eds_file.eds, view, report, std::cout);
    return report.fits() ? kExitOk : kExitFailure;
  } catch (const std::invalid_argument& error) {
    std::cerr << "cambio eds check: " << rig->source_file << ": " << error.what() << "\n";
    return kExitBadInput;
  }
}

}  // namespace

int run_eds_command(std::span<const std::string> args) {
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::cout << "usage: cambio eds check VENDOR.eds --rig RIG --group G [--node-id N]\n"
                 "  check   whether a drive's EDS fits a rig's CAN joint group "
                 "(cambio eds check --help)\n";
    return kExitOk;
  }
  if (args.empty() || args[0] != kSubcommands) {
    throw UsageError("eds: " +
                     (args.empty() ? std::string("expected a subcommand")
                                   : "unknown subcommand '" + args[0] + "'") +
                     " (the subcommands are: " + std::string(kSubcommands) + ")");
  }
  return run_check(args.subspan(1));
}

}  // namespace cambio::app
