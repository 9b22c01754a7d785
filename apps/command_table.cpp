#include <array>

#include "command.hpp"

namespace cambio::app {

// One declaration and one table row per subcommand; each lives in <name>_command.cpp.
int run_check_config_command(std::span<const std::string> args);
int run_loop_bench_command(std::span<const std::string> args);
int run_run_command(std::span<const std::string> args);
int run_console_command(std::span<const std::string> args);
int run_render_command(std::span<const std::string> args);
int run_sim_bench_command(std::span<const std::string> args);
int run_perceive_command(std::span<const std::string> args);
int run_perception_bench_command(std::span<const std::string> args);
int run_virtual_rig_command(std::span<const std::string> args);
int run_can_bench_command(std::span<const std::string> args);
int run_gaze_bench_command(std::span<const std::string> args);
int run_eds_command(std::span<const std::string> args);
int run_calibrate_command(std::span<const std::string> args);
int run_export_command(std::span<const std::string> args);
int run_node_command(std::span<const std::string> args);

std::span<const Command> all_commands() {
  static const std::array kCommands = {
      Command{"run", "run an experiment (the main job)", &run_run_command},
      Command{"console", "drive an experiment's robot with typed or piped commands",
              &run_console_command},
      Command{"check-config", "validate a rig file and print its summary",
              &run_check_config_command},
      Command{"loop-bench", "measure loop wake-up latency on this machine",
              &run_loop_bench_command},
      Command{"render", "render the eyes, depth and an overview of the sim at a pose",
              &run_render_command},
      Command{"sim-bench", "measure sim physics steps/s and stereo camera frames/s",
              &run_sim_bench_command},
      Command{"perceive", "run the Sensory Servo Module once on an image pair",
              &run_perceive_command},
      Command{"perception-bench", "time the SSM against memcpy and full-image OpenCV",
              &run_perception_bench_command},
      Command{"virtual-rig", "emulate the rig's CiA 402 drives on its CAN interfaces",
              &run_virtual_rig_command},
      Command{"eds", "check a vendor drive's EDS against a rig's CAN joint group (eds check)",
              &run_eds_command},
      Command{"calibrate",
              "from chessboard views: a stereo pair's intrinsics, distortion and pose; a "
              "camera's mount on its link",
              &run_calibrate_command},
      Command{"export", "the rig as a URDF for ROS tools (export urdf)", &run_export_command},
      Command{"node", "the perception host of a run split across machines (node perception)",
              &run_node_command},
      Command{"can-bench", "time the CANopen master and count the bus load (in-process bus)",
              &run_can_bench_command},
      Command{"gaze-bench", "score the gaze behaviour on generated scenes against the sim's truth",
              &run_gaze_bench_command},
  };
  return kCommands;
}

}  // namespace cambio::app
