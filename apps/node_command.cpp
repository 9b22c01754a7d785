// `cambio node perception EXPERIMENT.yaml`: the perception host of a split run. The robot runs
// `cambio run` with `ros2.split: perception_remote`; this node, on another machine of the same
// network (or the same one), takes its stereo pairs over DDS, runs the Sensory Servo Module with
// the experiment's settings, and sends each result back. Serves until stopped (SIGINT/SIGTERM)
// or --duration.
#include <iostream>
#include <optional>
#include <string>
#include <string_view>

#include "argument_parser.hpp"
#include "cambio/config/config_error.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/ros2/perception_link.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "run_outcome.hpp"
#include "stereo_ssm_config.hpp"
#include "stop_signal.hpp"

namespace cambio::app {
namespace {

constexpr std::string_view kNodeKinds = "perception";

void print_counts(const ros2::PerceptionNodeCounts& c) {
  std::cout << "perception node: " << c.images_received << " images (" << c.images_malformed
            << " refused), " << c.pairs_processed << " pairs processed (" << c.pairs_rejected
            << " refused by the SSM), " << c.results_sent << " results sent, "
            << c.requests_received << " requests (" << c.requests_malformed << " refused), SSM "
            << c.ssm_median_us << " us median per pair"
            << (c.write_errors > 0 ? ", WRITE ERRORS: " : "")
            << (c.write_errors > 0 ? std::to_string(c.write_errors) : "") << "\n";
  if (!c.last_problem.empty()) std::cout << "  last refused: " << c.last_problem << "\n";
}

int run_perception_node(std::span<const std::string> args) {
  ArgumentParser parser("node perception",
                        "EXPERIMENT.yaml [--set KEY=VALUE]... [--domain N] [--duration S]");
  parser
      .positional("EXPERIMENT.yaml",
                  "the robot's experiment: its rig's stereo pair and its perception settings")
      .repeated_option("set", "KEY=VALUE", "override a key, as `cambio run` does")
      .option("domain", "N", "the ROS 2 domain (default: the experiment's ros2.domain_id, or 0)")
      .option("duration", "S", "stop after S seconds of wall time (default: until signalled)");
  if (!parser.parse(args)) return kExitOk;
  const auto& stop = install_stop_signal_handlers();
  std::optional<config::ExperimentConfig> loaded =
      load_experiment_or_report(*parser.positional_value("EXPERIMENT.yaml"), parser.values("set"));
  if (!loaded) return kExitBadInput;
  const config::ExperimentConfig& experiment = *loaded;

  const long long domain = parser.integer(
      "domain", experiment.ros2 ? experiment.ros2->domain_id : 0, config::Range::closed(0, 232),
      "RTPS's ports for a higher domain exceed 65535");
  const double duration_s =
      parser.number("duration", 0.0, config::Range::closed(0.0, 1e7), "seconds of wall time");
  const hal::HardwareInfo hardware = config::hardware_description(experiment.rig);
  if (!hardware.stereo) {
    std::cerr << "cambio node perception: rig '" << experiment.rig.name
              << "' has no stereo pair (rig.stereo): nothing to perceive\n";
    return kExitBadInput;
  }
  const hal::CameraInfo* left = hardware.find_camera(hardware.stereo->left_camera);
  const hal::CameraInfo* right = hardware.find_camera(hardware.stereo->right_camera);
  const auto index = [&](const hal::CameraInfo* camera) {
    return static_cast<std::size_t>(camera - hardware.cameras.data());
  };
  ros2::PerceptionNodeSettings settings;
  settings.domain_id = static_cast<std::uint32_t>(domain);
  settings.cameras = {*left, *right};
  std::optional<ros2::PerceptionNode> node;
  try {
    node.emplace(settings, stereo_ssm_config(experiment, hardware, index(left), index(right)));
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  } catch (const std::invalid_argument& error) {
    std::cerr << "cambio node perception: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const std::runtime_error& error) {
    std::cerr << "cambio node perception: " << error.what() << "\n";
    return kExitDeviceFault;
  }
  std::cerr << "cambio node perception: serving rig '" << experiment.rig.name
            << "' on ROS 2 domain " << domain << ": pairs from /" << left->name
            << "/image_raw and /" << right->name << "/image_raw, results on "
            << ros2::kSsmSummaryTopic << "\n";
  node->serve(stop, duration_s);
  print_counts(node->counts());
  if (stop.load()) {
    const int signal_number = stop_signal_number();
    std::cerr << "cambio node perception: stopped by " << stop_signal_name(signal_number) << "\n";
    return exit_status_for_signal(signal_number);
  }
  return kExitOk;
}

}  // namespace

int run_node_command(std::span<const std::string> args) {
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::cout << "usage: cambio node perception EXPERIMENT.yaml [--domain N] [--duration S]\n"
                 "  perception   the perception host of a run split with "
                 "ros2.split: perception_remote\n";
    return kExitOk;
  }
  if (args.empty() || args[0] != kNodeKinds) {
    throw UsageError("node: " +
                     (args.empty() ? std::string("expected a node kind")
                                   : "unknown node kind '" + args[0] + "'") +
                     " (the node kinds are: " + std::string(kNodeKinds) + ")");
  }
  return run_perception_node(args.subspan(1));
}

}  // namespace cambio::app
