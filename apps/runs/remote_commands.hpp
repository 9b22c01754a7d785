#pragma once

// Console lines from ROS 2 (/cambio/command, std_msgs/String): the console's own parser and
// checks, on the bridge's command thread, for the commands that act on the robot (look, saccade,
// pursue, hold, verge, move, reach, grasp, release, home). Commands about the session itself
// (help, status, ssm, wait, quit) are refused: a remote node has its own topics to read and its
// own clock. A refusal comes back as the text the console would print.

#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "console_session.hpp"

namespace cambio::app {

/// The names `look object NAME` accepts: the simulator's scene objects.
std::vector<std::string> scene_object_names(const config::ExperimentConfig& experiment);

class RemoteCommands {
 public:
  RemoteCommands(MainJob& job, const config::ExperimentConfig& experiment);

  /// Carries out `line`; "" when done, else why not (one line per reason).
  std::string carry_out(const std::string& line);

 private:
  std::mutex mutex_;  // One command thread today; a second would not interleave sessions.
  std::ostringstream out_;
  ConsoleSession session_;
};

}  // namespace cambio::app
