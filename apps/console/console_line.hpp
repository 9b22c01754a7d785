#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace cambio::app {

/// The commands of `cambio console` (the paper's standard-input commands), one per line. Angles
/// are radians unless written with a unit ("30deg", "0.5rad"); points are metres in the robot's
/// base frame (x forward, y left, z up); pixels are the dominant eye's (u right, v down).
namespace console {

struct Help {
  std::string topic;  ///< Empty: every command.
};
struct Quit {};
struct Status {};
/// Advance `seconds` of simulated time before the next command is read.
struct Wait {
  double seconds = 0.0;
};
/// Move one joint to an angle (checked against its limits by the console, which says what it
/// clamped).
struct MoveJoint {
  std::string joint;
  double angle_rad = 0.0;
};
enum class TargetKind { kPixel, kPoint, kAngles, kObject };
struct Target {
  TargetKind kind = TargetKind::kPixel;
  std::array<double, 3> values{};  ///< pixel (u, v), point (x, y, z) m, angles (pan, tilt) rad.
  std::string object;              ///< kObject: a scene object's name.
};
/// Fixate a target (visual servoing); `look` is its synonym.
struct Look {
  Target target;
};
struct Saccade {
  Target target;
};
struct Pursue {};
struct Hold {};
/// Vergence of the other eye on what the dominant eye fixates, on or off.
struct Verge {
  bool on = true;
};
enum class Arm { kNearest, kLeft, kRight };
/// Reach with an arm (the nearer by default) what the head fixates, or a point; the arm stops on
/// its touch sensor.
struct Reach {
  bool fixation = true;           ///< False: `point`.
  std::array<double, 3> point{};  ///< x, y, z (m), base frame.
  Arm arm = Arm::kNearest;
};
/// Close (grasp) or open (release) a gripper.
struct Gripper {
  bool close = true;
  Arm arm = Arm::kNearest;
};
/// Home a joint's drive again (CiA 402 homing), or every joint that lost its reference.
struct Home {
  std::string joint;  ///< Empty: every joint that must home and has not since its drive booted.
};
/// Request SSM features and print them; with a directory, also save the maps as PNG.
struct Ssm {
  std::string save_directory;
};

/// Save a camera's newest image with the joints' readings (a hand-eye calibration's view).
struct Capture {
  std::string camera;
  std::string directory;
};

using Command = std::variant<Help, Quit, Status, Wait, MoveJoint, Look, Saccade, Pursue, Hold,
                             Verge, Reach, Gripper, Home, Ssm, Capture>;

/// A line that is not a command: what was expected, and where (the word, 1-based).
struct ParseError {
  std::string message;
};

/// Parses one line. Blank lines and lines starting with '#' give nullopt (nothing to do).
/// Never throws on any input; an unknown command suggests the nearest one.
std::optional<std::variant<Command, ParseError>> parse(std::string_view line);

/// One line per command: its syntax and what it does (for `help`).
std::vector<std::string> help_lines();

}  // namespace console
}  // namespace cambio::app
