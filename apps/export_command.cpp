// `cambio export urdf RIG [--set key.path=value]...`: the rig as a URDF on standard output (the
// same text a run with `ros2:` publishes on /robot_description), for RViz, Foxglove or
// robot_state_publisher: `cambio export urdf cambio > cambio.urdf`.
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "argument_parser.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/ros2/urdf_export.hpp"
#include "command.hpp"
#include "config_errors.hpp"

namespace cambio::app {
namespace {

constexpr std::string_view kSubcommands = "urdf";

int run_urdf(std::span<const std::string> args) {
  ArgumentParser parser("export urdf", "RIG [--set key.path=value]...");
  parser.positional("RIG", "rig file or shipped rig name, e.g. cambio or pan_tilt")
      .repeated_option("set", "KEY.PATH=VALUE",
                       "override a rig key first, e.g. --set joints.neck_pan.max_position_deg=60");
  if (!parser.parse(args)) return kExitOk;
  const auto overrides = parse_overrides_or_report(parser.values("set"));
  if (!overrides) return kExitBadInput;
  const auto rig = load_rig_or_report(
      config::resolve_config_argument("rigs", *parser.positional_value("RIG")), *overrides);
  if (!rig) return kExitBadInput;
  std::cout << ros2::make_urdf(config::hardware_description(*rig), rig->name);
  std::cout.flush();
  if (!std::cout) {
    std::cerr << "cambio export urdf: cannot write the URDF to standard output\n";
    return kExitBadInput;
  }
  return kExitOk;
}

}  // namespace

int run_export_command(std::span<const std::string> args) {
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::cout << "usage: cambio export urdf RIG [--set key.path=value]...\n"
                 "  urdf   the rig as a URDF on standard output (cambio export urdf --help)\n";
    return kExitOk;
  }
  if (args.empty() || args[0] != kSubcommands) {
    throw UsageError("export: " +
                     (args.empty() ? std::string("expected a subcommand")
                                   : "unknown subcommand '" + args[0] + "'") +
                     " (the subcommands are: " + std::string(kSubcommands) + ")");
  }
  return run_urdf(args.subspan(1));
}

}  // namespace cambio::app
