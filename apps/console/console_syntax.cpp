#include "console_line.hpp"
#include "console_line_detail.hpp"

namespace cambio::app::console {

namespace detail {
namespace {

constexpr Syntax kCommands[] = {
    {"help", "help [COMMAND]", "list the commands, or describe one"},
    {"quit", "quit", "stop the run (the drives are stopped and disabled) and exit"},
    {"status", "status", "the believed and the true state: joints, gaze, disparity"},
    {"wait", "wait SECONDS", "advance SECONDS of simulated time before reading the next command"},
    {"move", "move JOINT ANGLE", "move a joint to ANGLE (rad, or 30deg), within its limits"},
    {"look", "look pixel U V | point X Y Z | angles PAN TILT | object NAME",
     "fixate a target with visual servoing (the dominant eye; the other verges)"},
    {"saccade", "saccade pixel U V | point X Y Z | angles PAN TILT | object NAME",
     "jump to a target at the joints' limits, then fixate it"},
    {"pursue", "pursue", "follow what the dominant eye's fovea sees move"},
    {"hold", "hold", "keep the head where it is commanded now"},
    {"verge", "verge on|off", "the other eye verges on what the dominant eye fixates, or not"},
    {"reach", "reach [fixation | point X Y Z] [left|right]",
     "reach what the head fixates (stereo estimate) or a point with the nearer arm, or the one "
     "named; it stops on its touch sensor"},
    {"grasp", "grasp [left|right]", "close the named arm's gripper, or both"},
    {"release", "release [left|right]", "open the named arm's gripper, or both"},
    {"home", "home [JOINT]",
     "home a joint's drive again (CiA 402 homing), or every joint whose drive lost its "
     "reference; it is then enabled where it homed"},
    {"ssm", "ssm [save DIR]", "print the SSM's features at the foveas; save the maps as PNG"},
    {"capture", "capture CAMERA|stereo DIR",
     "save the camera's newest image and the joints' readings as viewNN.png and viewNN.yaml in "
     "DIR (the views of cambio calibrate hand-eye); stereo: both images of the newest pair as "
     "leftNN.png and rightNN.png, with pairNN.yaml (the views of cambio calibrate stereo)"},
};

}  // namespace

std::vector<std::string> command_names() {
  std::vector<std::string> names;
  for (const auto& command : kCommands) names.emplace_back(command.name);
  return names;
}

const Syntax* find_syntax(std::string_view name) {
  for (const auto& command : kCommands) {
    if (name == command.name) return &command;
  }
  return nullptr;
}

}  // namespace detail

std::vector<std::string> help_lines() {
  std::vector<std::string> lines;
  for (const auto& command : detail::kCommands) {
    lines.push_back(std::string(command.usage) + "\n    " + command.what);
  }
  return lines;
}

}  // namespace cambio::app::console
