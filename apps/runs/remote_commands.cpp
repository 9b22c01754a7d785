#include "remote_commands.hpp"

#include <string_view>
#include <variant>

namespace cambio::app {

std::vector<std::string> scene_object_names(const config::ExperimentConfig& experiment) {
  std::vector<std::string> objects;
  if (experiment.scene) {
    for (const auto& object : experiment.scene->objects) objects.push_back(object.name);
  }
  return objects;
}

namespace {

/// Whether `command` acts on the robot (what a remote node may send).
bool acts_on_the_robot(const console::Command& command) {
  return std::visit(
      [](const auto& c) {
        using T = std::decay_t<decltype(c)>;
        return !(std::is_same_v<T, console::Help> || std::is_same_v<T, console::Quit> ||
                 std::is_same_v<T, console::Status> || std::is_same_v<T, console::Wait> ||
                 std::is_same_v<T, console::Ssm> || std::is_same_v<T, console::Capture>);
      },
      command);
}

}  // namespace

RemoteCommands::RemoteCommands(MainJob& job, const config::ExperimentConfig& experiment)
    : session_(job, *job.actions(), scene_object_names(experiment), out_) {}

std::string RemoteCommands::carry_out(const std::string& line) {
  const auto parsed = console::parse(line);
  if (!parsed) return "an empty line or a comment: nothing to do";
  if (const auto* command = std::get_if<console::Command>(&*parsed)) {
    if (!acts_on_the_robot(*command)) {
      const std::string name = line.substr(line.find_first_not_of(" \t"));
      return "'" + name.substr(0, name.find_first_of(" \t")) +
             "' is for the console's own session, not a remote command (look, saccade, pursue, "
             "hold, verge, move, reach, grasp, release, home)";
    }
  }
  const std::lock_guard lock(mutex_);
  out_.str("");
  (void)session_.execute(line, 0);
  // What the console would have printed: its refusals (and parse errors) are the answer.
  std::istringstream printed(out_.str());
  std::string reasons;
  for (std::string text; std::getline(printed, text);) {
    for (const std::string_view prefix : {"refused: ", "error: ", "refused by "}) {
      if (text.rfind(prefix, 0) != 0) continue;
      // "refused by the gaze loop: ..." keeps who refused; the others say it by being here.
      const std::size_t from = prefix == "refused by " ? 0 : prefix.size();
      reasons += (reasons.empty() ? "" : "; ") + text.substr(from);
      break;
    }
  }
  return reasons;
}

}  // namespace cambio::app
