// The console's command lines: every command, and every class of bad line refused with what was
// expected (a bad line never stops a run).
#include "console_line.hpp"

#include <numbers>

#include <gtest/gtest.h>

namespace cambio::app::console {
namespace {

Command ok(std::string_view line) {
  const auto parsed = parse(line);
  EXPECT_TRUE(parsed.has_value()) << line;
  if (!parsed) return Help{};
  if (const auto* error = std::get_if<ParseError>(&*parsed)) {
    ADD_FAILURE() << line << ": " << error->message;
    return Help{};
  }
  return std::get<Command>(*parsed);
}

std::string error(std::string_view line) {
  const auto parsed = parse(line);
  EXPECT_TRUE(parsed.has_value()) << line;
  if (!parsed) return {};
  const auto* failure = std::get_if<ParseError>(&*parsed);
  EXPECT_NE(failure, nullptr) << line << " parsed";
  return failure != nullptr ? failure->message : std::string{};
}

TEST(ConsoleCommand, BlankLinesAndCommentsAreNothingToDo) {
  EXPECT_FALSE(parse("").has_value());
  EXPECT_FALSE(parse("   \t ").has_value());
  EXPECT_FALSE(parse("# a comment").has_value());
}

TEST(ConsoleCommand, EveryCommandParses) {
  EXPECT_TRUE(std::holds_alternative<Quit>(ok("quit")));
  EXPECT_TRUE(std::holds_alternative<Status>(ok("  status  # with a comment")));
  EXPECT_DOUBLE_EQ(std::get<Wait>(ok("wait 0.25")).seconds, 0.25);
  const auto move = std::get<MoveJoint>(ok("move neck_pan 30deg"));
  EXPECT_EQ(move.joint, "neck_pan");
  EXPECT_NEAR(move.angle_rad, std::numbers::pi / 6, 1e-12);
  EXPECT_DOUBLE_EQ(std::get<MoveJoint>(ok("move eye_tilt -0.1")).angle_rad, -0.1);
  EXPECT_DOUBLE_EQ(std::get<MoveJoint>(ok("move eye_tilt 0.2rad")).angle_rad, 0.2);
  const auto look = std::get<Look>(ok("look pixel 320 240.5"));
  EXPECT_EQ(look.target.kind, TargetKind::kPixel);
  EXPECT_DOUBLE_EQ(look.target.values[1], 240.5);
  const auto point = std::get<Saccade>(ok("saccade point 1.0 -0.16 1.4"));
  EXPECT_EQ(point.target.kind, TargetKind::kPoint);
  EXPECT_DOUBLE_EQ(point.target.values[1], -0.16);
  const auto angles = std::get<Look>(ok("look angles 10deg -5deg"));
  EXPECT_NEAR(angles.target.values[0], 10 * std::numbers::pi / 180, 1e-12);
  EXPECT_EQ(std::get<Look>(ok("look object textured_sphere")).target.object, "textured_sphere");
  EXPECT_TRUE(std::holds_alternative<Pursue>(ok("pursue")));
  EXPECT_TRUE(std::holds_alternative<Hold>(ok("hold")));
  EXPECT_FALSE(std::get<Verge>(ok("verge off")).on);
  EXPECT_TRUE(std::get<Ssm>(ok("ssm")).save_directory.empty());
  EXPECT_EQ(std::get<Ssm>(ok("ssm save out/maps")).save_directory, "out/maps");
  EXPECT_EQ(std::get<Help>(ok("help saccade")).topic, "saccade");
  const auto reach = std::get<Reach>(ok("reach"));
  EXPECT_TRUE(reach.fixation);
  EXPECT_EQ(reach.arm, Arm::kNearest);
  EXPECT_EQ(std::get<Reach>(ok("reach fixation right")).arm, Arm::kRight);
  const auto reach_point = std::get<Reach>(ok("reach point 0.5 0.1 0.9 left"));
  EXPECT_FALSE(reach_point.fixation);
  EXPECT_DOUBLE_EQ(reach_point.point[2], 0.9);
  EXPECT_EQ(reach_point.arm, Arm::kLeft);
  EXPECT_TRUE(std::get<Gripper>(ok("grasp")).close);
  const auto release = std::get<Gripper>(ok("release right"));
  EXPECT_FALSE(release.close);
  EXPECT_EQ(release.arm, Arm::kRight);
  EXPECT_EQ(std::get<Home>(ok("home neck_pan")).joint, "neck_pan");
  EXPECT_TRUE(std::get<Home>(ok("home")).joint.empty()) << "every joint that lost its reference";
}

TEST(ConsoleCommand, HelpOnSomethingThatIsNoCommandIsRefusedNotAnsweredBySilence) {
  const std::string message = error("help zzz");
  EXPECT_NE(message.find("a command to describe, found \"zzz\""), std::string::npos) << message;
  EXPECT_NE(message.find("saccade"), std::string::npos) << message;  // The commands are listed.
  EXPECT_NE(error("help sacade").find("did you mean \"saccade\"?"), std::string::npos);
  // A prefix is no topic: "re" would have matched reach and release.
  EXPECT_FALSE(error("help re").empty());
}

TEST(ConsoleCommand, AnUnknownCommandSuggestsTheNearest) {
  EXPECT_EQ(error("sacade point 1 0 1"), "unknown command \"sacade\"; did you mean \"saccade\"?");
  EXPECT_EQ(error("fly"), "unknown command \"fly\"; type help for the commands");
  // What a terminal would act on is echoed escaped, and a long word is cut.
  EXPECT_EQ(error("\x1b[2Jfly"), "unknown command \"\\x1b[2Jfly\"; type help for the commands");
  const std::string message = error(std::string(5000, 'x'));
  EXPECT_LT(message.size(), 200u);
  EXPECT_NE(message.find("... (5000 bytes)"), std::string::npos) << message;
}

TEST(ConsoleCommand, BadArgumentsSayWhatWasExpected) {
  EXPECT_EQ(error("wait"), "wait: expected a number of seconds (usage: wait SECONDS)");
  EXPECT_EQ(error("wait -1"),
            "wait: expected seconds in [0, 86400], found -1 (usage: wait SECONDS)");
  // Longer than any run (and past the int64 nanosecond clock at 9.2e9 s): refused, not wrapped.
  EXPECT_EQ(error("wait 1e12"),
            "wait: expected seconds in [0, 86400], found 1e12 (usage: wait SECONDS)");
  EXPECT_EQ(error("wait soon"),
            "wait: expected a number of seconds, found \"soon\" (usage: wait SECONDS)");
  EXPECT_NE(error("move neck_pan fast").find("an angle (rad, or with deg), found \"fast\""),
            std::string::npos);
  EXPECT_NE(error("look pixel 10").find("expected a pixel row V"), std::string::npos);
  EXPECT_NE(error("look there").find("a target (pixel, point, angles or object), found \"there\""),
            std::string::npos);
  EXPECT_NE(error("verge maybe").find("on or off, found \"maybe\""), std::string::npos);
  EXPECT_NE(error("quit now").find("nothing after quit, found \"now\""), std::string::npos);
  EXPECT_NE(error("wait nan").find("found \"nan\""), std::string::npos);
  EXPECT_NE(error("wait inf").find("found \"inf\""), std::string::npos);
  EXPECT_NE(error("ssm keep x").find("nothing or save DIR"), std::string::npos);
  EXPECT_NE(error("reach point 0.5 0.1").find("expected Z (m)"), std::string::npos);
  EXPECT_NE(error("grasp both").find("left, right or nothing, found \"both\""), std::string::npos);
  EXPECT_NE(error("reach up").find("left, right or nothing, found \"up\""), std::string::npos);
  EXPECT_NE(error("home pan tilt").find("nothing after pan, found \"tilt\""), std::string::npos);
  EXPECT_NE(error("capture left_eye").find("a directory after the camera"), std::string::npos);
}

TEST(ConsoleCommand, HelpListsEveryCommand) {
  const auto lines = help_lines();
  EXPECT_EQ(lines.size(), 16U);
  for (const char* name :
       {"help", "quit", "status", "wait", "move", "look", "saccade", "pursue", "hold", "verge",
        "reach", "grasp", "release", "home", "ssm", "capture"}) {
    bool found = false;
    for (const auto& line : lines) found = found || line.rfind(name, 0) == 0;
    EXPECT_TRUE(found) << name;
  }
}

}  // namespace
}  // namespace cambio::app::console
