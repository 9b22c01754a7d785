#include "console_line.hpp"

#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>

#include "cambio/config/echoed_text.hpp"
#include "cambio/config/experiment_config.hpp"
#include "cambio/config/map_reader.hpp"
#include "console_line_detail.hpp"

namespace cambio::app::console {

namespace {

using detail::Syntax;

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
    syntax_ = detail::find_syntax(name);
    if (syntax_ == nullptr) return unknown_command(name);
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
  static ParseError unknown_command(const std::string& name) {
    std::string message = "unknown command " + config::in_quotes(name);
    if (const auto near = config::closest_name(name, detail::command_names())) {
      message += "; did you mean " + config::in_quotes(*near) + "?";
    } else {
      message += "; type help for the commands";
    }
    return ParseError{message};
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw ParseError{std::string(syntax_->name) + ": expected " + what +
                     " (usage: " + syntax_->usage + ")"};
  }

  bool more() const { return next_ < words_.size(); }

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

  std::array<double, 3> point_words() {
    std::array<double, 3> p{};
    p[0] = number_word("X (m)");
    p[1] = number_word("Y (m)");
    p[2] = number_word("Z (m)");
    return p;
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
      t.values = point_words();
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
      if (more()) {
        help.topic = words_[next_++];
        // A topic that names no command is refused like any bad line, never answered by silence.
        if (detail::find_syntax(help.topic) == nullptr) {
          std::string known;
          for (const auto& command : detail::command_names()) known += " " + command;
          std::string near;
          if (const auto closest = config::closest_name(help.topic, detail::command_names())) {
            near = "; did you mean " + config::in_quotes(*closest) + "?";
          }
          fail("a command to describe, found " + config::in_quotes(help.topic) + near +
               " (commands:" + known + ")");
        }
      }
      return help;
    }
    if (name == "quit") return Quit{};
    if (name == "status") return Status{};
    if (name == "pursue") return Pursue{};
    if (name == "hold") return Hold{};
    if (name == "wait") return parse_wait();
    if (name == "move") return parse_move();
    if (name == "look") return Look{target()};
    if (name == "saccade") return Saccade{target()};
    if (name == "verge") return parse_verge();
    if (name == "reach") return parse_reach();
    if (name == "grasp" || name == "release") return Gripper{name == "grasp", arm()};
    if (name == "home") return Home{more() ? words_[next_++] : std::string()};
    if (name == "capture") {
      Capture capture;
      capture.camera = word("a camera");
      capture.directory = word("a directory after the camera");
      return capture;
    }
    return parse_ssm();  // The one name left: find_syntax() knew it.
  }

  Wait parse_wait() {
    const double seconds = number_word("a number of seconds");
    // At most an experiment's longest run: the simulated clock counts int64 nanoseconds.
    if (seconds < 0.0 || seconds > config::kMaxExperimentDuration_s) {
      fail("seconds in [0, " + std::to_string(static_cast<int>(config::kMaxExperimentDuration_s)) +
           "], found " + config::echoed(words_[next_ - 1]));
    }
    return Wait{seconds};
  }

  MoveJoint parse_move() {
    MoveJoint move;
    move.joint = word("a joint's name");
    move.angle_rad = angle_word("an angle");
    return move;
  }

  Verge parse_verge() {
    const std::string& state = word("on or off");
    if (state != "on" && state != "off") fail("on or off, found " + config::in_quotes(state));
    return Verge{state == "on"};
  }

  Reach parse_reach() {
    Reach reach;
    if (more() && words_[next_] == "point") {
      ++next_;
      reach.fixation = false;
      reach.point = point_words();
    } else if (more() && words_[next_] == "fixation") {
      ++next_;
    }
    reach.arm = arm();
    return reach;
  }

  Ssm parse_ssm() {
    Ssm ssm;
    if (more()) {
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

}  // namespace cambio::app::console
