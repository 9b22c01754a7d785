#include "console_line.hpp"

#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>

#include "cambio/config/echoed_text.hpp"
#include "cambio/config/experiment_config.hpp"
#include "cambio/config/map_reader.hpp"

namespace cambio::app::console {

namespace {

struct Syntax {
  const char* name;
  const char* usage;
  const char* what;
};

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
    {"ssm", "ssm [save DIR]", "print the SSM's features at the foveas; save the maps as PNG"},
};

std::vector<std::string> command_names() {
  std::vector<std::string> names;
  for (const auto& command : kCommands) names.emplace_back(command.name);
  return names;
}

const Syntax* find(std::string_view name) {
  for (const auto& command : kCommands) {
    if (name == command.name) return &command;
  }
  return nullptr;
}

std::vector<std::string> split(std::string_view line) {
  std::vector<std::string> words;
  std::istringstream in{std::string(line)};
  std::string word;
  while (in >> word) words.push_back(word);
  return words;
}

// A finite number, the whole word.
std::optional<double> number(std::string_view word) {
  double value = 0.0;
  const char* end = word.data() + word.size();
  const auto [ptr, error] = std::from_chars(word.data(), end, value);
  if (error != std::errc{} || ptr != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

// An angle: a number of radians, or with a "deg" or "rad" suffix.
std::optional<double> angle_rad(std::string_view word) {
  double scale = 1.0;
  if (word.size() > 3 && word.substr(word.size() - 3) == "deg") {
    scale = std::numbers::pi / 180.0;
    word.remove_suffix(3);
  } else if (word.size() > 3 && word.substr(word.size() - 3) == "rad") {
    word.remove_suffix(3);
  }
  const auto value = number(word);
  if (!value) return std::nullopt;
  return *value * scale;
}

class Parser {
 public:
  explicit Parser(std::vector<std::string> words) : words_(std::move(words)) {}

  std::variant<Command, ParseError> run() {
    const std::string& name = words_[0];
    syntax_ = find(name);
    if (syntax_ == nullptr) {
      std::string message = "unknown command " + config::in_quotes(name);
      if (const auto near = config::closest_name(name, command_names())) {
        message += "; did you mean " + config::in_quotes(*near) + "?";
      } else {
        message += "; type help for the commands";
      }
      return ParseError{message};
    }
    try {
      Command command = parse_command(name);
      if (words_.size() > next_) {
        fail("nothing after " + config::echoed(words_[next_ - 1]) + ", found " +
             config::in_quotes(words_[next_]));
      }
      return command;
    } catch (const ParseError& error) {
      return error;
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw ParseError{std::string(syntax_->name) + ": expected " + what +
                     " (usage: " + syntax_->usage + ")"};
  }

  const std::string& word(const char* what) {
    if (next_ >= words_.size()) fail(what);
    return words_[next_++];
  }

  double number_word(const char* what) {
    const std::string& text = word(what);
    const auto value = number(text);
    if (!value) fail(std::string(what) + ", found " + config::in_quotes(text));
    return *value;
  }

  double angle_word(const char* what) {
    const std::string& text = word(what);
    const auto value = angle_rad(text);
    if (!value) fail(std::string(what) + " (rad, or with deg), found " + config::in_quotes(text));
    return *value;
  }

  Target target() {
    const std::string& kind = word("a target: pixel, point, angles or object");
    Target t;
    if (kind == "pixel") {
      t.kind = TargetKind::kPixel;
      t.values[0] = number_word("a pixel column U");
      t.values[1] = number_word("a pixel row V");
    } else if (kind == "point") {
      t.kind = TargetKind::kPoint;
      t.values[0] = number_word("X (m)");
      t.values[1] = number_word("Y (m)");
      t.values[2] = number_word("Z (m)");
    } else if (kind == "angles") {
      t.kind = TargetKind::kAngles;
      t.values[0] = angle_word("a pan angle");
      t.values[1] = angle_word("a tilt angle");
    } else if (kind == "object") {
      t.kind = TargetKind::kObject;
      t.object = word("a scene object's name");
    } else {
      fail("a target (pixel, point, angles or object), found " + config::in_quotes(kind));
    }
    return t;
  }

  // An optional trailing arm name.
  Arm arm() {
    if (next_ >= words_.size()) return Arm::kNearest;
    const std::string& side = word("left or right");
    if (side == "left") return Arm::kLeft;
    if (side == "right") return Arm::kRight;
    if (side == "nearest") return Arm::kNearest;
    fail("left, right or nothing, found " + config::in_quotes(side));
  }

  Command parse_command(const std::string& name) {
    next_ = 1;
    if (name == "help") {
      Help help;
      if (next_ < words_.size()) help.topic = words_[next_++];
      return help;
    }
    if (name == "quit") return Quit{};
    if (name == "status") return Status{};
    if (name == "pursue") return Pursue{};
    if (name == "hold") return Hold{};
    if (name == "wait") {
      const double seconds = number_word("a number of seconds");
      // At most an experiment's longest run: the simulated clock counts int64 nanoseconds.
      if (seconds < 0.0 || seconds > config::kMaxExperimentDuration_s) {
        fail("seconds in [0, " +
             std::to_string(static_cast<int>(config::kMaxExperimentDuration_s)) + "], found " +
             config::echoed(words_[next_ - 1]));
      }
      return Wait{seconds};
    }
    if (name == "move") {
      MoveJoint move;
      move.joint = word("a joint's name");
      move.angle_rad = angle_word("an angle");
      return move;
    }
    if (name == "look") return Look{target()};
    if (name == "saccade") return Saccade{target()};
    if (name == "verge") {
      const std::string& state = word("on or off");
      if (state != "on" && state != "off") fail("on or off, found " + config::in_quotes(state));
      return Verge{state == "on"};
    }
    if (name == "reach") {
      Reach reach;
      if (next_ < words_.size() && words_[next_] == "point") {
        ++next_;
        reach.fixation = false;
        reach.point[0] = number_word("X (m)");
        reach.point[1] = number_word("Y (m)");
        reach.point[2] = number_word("Z (m)");
      } else if (next_ < words_.size() && words_[next_] == "fixation") {
        ++next_;
      }
      reach.arm = arm();
      return reach;
    }
    if (name == "grasp" || name == "release") return Gripper{name == "grasp", arm()};
    // ssm
    Ssm ssm;
    if (next_ < words_.size()) {
      const std::string& keyword = word("save");
      if (keyword != "save") fail("nothing or save DIR, found " + config::in_quotes(keyword));
      ssm.save_directory = word("a directory after save");
    }
    return ssm;
  }

  std::vector<std::string> words_;
  std::size_t next_ = 1;
  const Syntax* syntax_ = nullptr;
};

}  // namespace

std::optional<std::variant<Command, ParseError>> parse(std::string_view line) {
  const auto hash = line.find('#');
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  std::vector<std::string> words = split(line);
  if (words.empty()) return std::nullopt;
  return Parser(std::move(words)).run();
}

std::vector<std::string> help_lines() {
  std::vector<std::string> lines;
  for (const auto& command : kCommands) {
    lines.push_back(std::string(command.usage) + "\n    " + command.what);
  }
  return lines;
}

}  // namespace cambio::app::console
