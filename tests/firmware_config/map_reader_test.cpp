// Tests of firmware_config/src/map_reader.cpp: typed reads, their messages and locations.
#include "cambio/config/map_reader.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace cambio::config {
namespace {

struct Read {
  ConfigDocument document;
  MapReader root;
};

Read read(const std::string& yaml) {
  ConfigDocument document = ConfigDocument::from_string(yaml, "doc.yaml");
  MapReader root = document.root();
  return {std::move(document), std::move(root)};
}

TEST(EditDistance, CountsInsertionsDeletionsAndSubstitutions) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("abc", ""), 3u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("max_velocty_rad_s", "max_velocity_rad_s"), 1u);
}

TEST(ClosestName, SuggestsOnlyAPlausibleTypo) {
  const std::vector<std::string> names = {"joint", "control", "perception", "camera"};
  EXPECT_EQ(closest_name("contrl", names), "control");
  EXPECT_EQ(closest_name("percepton", names), "perception");
  // Two edits at most for short words (a quarter of the length for long ones).
  EXPECT_EQ(closest_name("xyz", names), std::nullopt);
  EXPECT_EQ(closest_name("jnt", names), "joint");
  EXPECT_EQ(closest_name("j", names), std::nullopt);
  EXPECT_EQ(closest_name("j", names, 4), "joint");
  EXPECT_EQ(closest_name("camera", {}), std::nullopt);
}

TEST(Range, DescribesItsBounds) {
  EXPECT_EQ(Range::positive().describe(), "> 0");
  EXPECT_EQ(Range::non_negative().describe(), ">= 0");
  EXPECT_EQ(Range::closed(1, 127).describe(), "in [1, 127]");
  EXPECT_EQ((Range{0, 1e5, true, false}).describe(), "in (0, 100000]");
  EXPECT_EQ(Range{}.describe(), "");
  EXPECT_TRUE(Range::closed(1, 127).contains(127));
  EXPECT_FALSE(Range::positive().contains(0));
}

TEST(MapReader, ReadsTypedValues) {
  auto [document, root] =
      read("n: 2.5\ni: -3\nb: true\nt: hello\nc: rgb8\na_deg: 90\nv: [1, 2, 3]\ns: [x, y]\n");
  EXPECT_EQ(root.number("n"), 2.5);
  EXPECT_EQ(root.integer("i"), -3);
  EXPECT_TRUE(root.boolean("b"));
  EXPECT_EQ(root.text("t"), "hello");
  EXPECT_EQ(root.choice("c", {"grey8", "rgb8"}), "rgb8");
  EXPECT_DOUBLE_EQ(root.angle_rad("a"), std::numbers::pi / 2);
  EXPECT_EQ(root.vector3("v"), (std::array<double, 3>{1, 2, 3}));
  EXPECT_EQ(root.strings("s"), (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(root.number_or("absent", 7.0), 7.0);
  root.finish();
  EXPECT_TRUE(document.issues()->empty());
}

TEST(MapReader, ReportsWrongTypesAtTheValueWithOneBasedLineAndColumn) {
  auto [document, root] = read("n: fast\ni: 2.5\nb: maybe\nq: \"2.0\"\nv: [1, x, 3]\n");
  root.number("n");
  root.integer("i");
  root.boolean("b");
  root.number("q");
  root.vector3("v");
  root.finish();
  const auto& issues = document.issues()->issues();
  ASSERT_EQ(issues.size(), 5u);
  EXPECT_EQ(issues[0].to_string(), "doc.yaml:1:4: n: expected a number, found \"fast\"");
  EXPECT_EQ(issues[1].to_string(), "doc.yaml:2:4: i: expected an integer, found 2.5");
  EXPECT_EQ(issues[2].to_string(), "doc.yaml:3:4: b: expected true or false, found \"maybe\"");
  // A quoted number is text: the user asked for a string.
  EXPECT_EQ(issues[3].to_string(), "doc.yaml:4:4: q: expected a number, found \"2.0\"");
  EXPECT_EQ(issues[4].to_string(), "doc.yaml:5:8: v[1]: expected a number, found \"x\"");
}

TEST(MapReader, ReportsAMissingKeyAtTheMapThatShouldHoldIt) {
  auto [document, root] = read("outer:\n  inner:\n    a: 1\n");
  MapReader inner = root.map("outer").map("inner");
  inner.number("b", Range::positive());
  const auto& issues = document.issues()->issues();
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].to_string(),
            "doc.yaml:3:5: outer.inner.b: missing key (expected a number > 0)");
}

TEST(MapReader, ReportsAnEmptyMapValueAtItsKey) {
  auto [document, root] = read("a: 1\nservo:\nb: 2\n");
  auto servo = root.optional_map("servo");
  ASSERT_TRUE(servo.has_value());
  const auto& issues = document.issues()->issues();
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].to_string(), "doc.yaml:2:1: servo: expected a map, found nothing");
}

TEST(MapReader, SuggestsTheClosestAcceptedKey) {
  auto [document, root] = read("max_velocty_rad_s: 1\nzzz: 2\n");
  root.number_or("max_velocity_rad_s", 0.0);
  root.number_or("rate_hz", 0.0);
  root.finish();
  const auto& issues = document.issues()->issues();
  ASSERT_EQ(issues.size(), 2u);
  EXPECT_EQ(issues[0].to_string(),
            "doc.yaml:1:1: max_velocty_rad_s: unknown key \"max_velocty_rad_s\"; did you mean "
            "\"max_velocity_rad_s\"?");
  EXPECT_EQ(issues[1].to_string(),
            "doc.yaml:2:1: zzz: unknown key \"zzz\"; expected one of max_velocity_rad_s, rate_hz");
}

TEST(MapReader, RefusesDuplicateKeys) {
  auto [document, root] = read("a: 1\nb: 2\na: 3\n");
  root.number("a");
  root.number("b");
  root.finish();
  const auto& issues = document.issues()->issues();
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].to_string(), "doc.yaml:3:1: a: duplicate key (first given at line 1)");
}

TEST(MapReader, RefusesAnAngleGivenInBothUnits) {
  auto [document, root] = read("x_deg: 10\nx_rad: 0.2\n");
  root.angle_rad("x");
  root.finish();
  const auto& issues = document.issues()->issues();
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].to_string(),
            "doc.yaml:2:1: x_rad: expected either x_deg or x_rad, found both");
}

TEST(MapReader, ChecksAnAngleInDegreesAgainstItsRangeInDegrees) {
  auto [document, root] = read("x_deg: 200\n");
  root.angle_rad("x", Range::closed(-std::numbers::pi, std::numbers::pi));
  const auto& issues = document.issues()->issues();
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].message, "expected a number in [-180, 180], found 200");
}

TEST(ConfigDocument, ReportsAYamlSyntaxErrorWithItsLine) {
  try {
    ConfigDocument::from_string("a: 1\nb: [1, 2\nc: 3\n", "bad.yaml");
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& error) {
    ASSERT_EQ(error.issues().size(), 1u);
    EXPECT_EQ(error.issues()[0].file, "bad.yaml");
    EXPECT_GT(error.issues()[0].line, 0);
    EXPECT_NE(error.issues()[0].message.find("invalid YAML"), std::string::npos);
  }
}

TEST(ConfigDocument, ReportsAMissingFile) {
  try {
    ConfigDocument::load_file("/nonexistent/rig.yaml");
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& error) {
    ASSERT_EQ(error.issues().size(), 1u);
    EXPECT_EQ(error.issues()[0].to_string(),
              "/nonexistent/rig.yaml: cannot read the file: it does not exist");
  }
}

// ---------------------------------------------------------------------------------------------
// What messages echo of the file is short and on one line.

TEST(Echo, AHugeValueIsCutToEightyCharacters) {
  // A 500 kB value was repeated whole in the message.
  auto [document, root] = read("rate_hz: " + std::string(500'000, '7') + "x\n");
  root.number("rate_hz", Range::positive());
  const auto& issues = document.issues()->issues();
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].message,
            "expected a number > 0, found \"" + std::string(80, '7') + "... (500001 bytes)\"");
}

TEST(Echo, AHugeNumberIsCutToo) {
  auto [document, root] = read("rate_hz: -" + std::string(100, '9') + "\n");
  root.number("rate_hz", Range::positive());
  const auto& issues = document.issues()->issues();
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].message,
            "expected a number > 0, found -" + std::string(79, '9') + "... (101 bytes)");
}

TEST(Echo, CutsBetweenCharactersAndEscapesLineBreaks) {
  // 81 two-byte characters: the cut falls after the 80th, not inside one.
  std::string accents;
  for (int i = 0; i < 81; ++i) accents += "\u00e9";
  auto [document, root] = read("n: \"" + accents + "\"\nother: \"a\\nb\\tc\"\n");
  root.number("n");
  root.number("other");
  const auto& issues = document.issues()->issues();
  ASSERT_EQ(issues.size(), 2u);
  EXPECT_EQ(issues[0].message,
            "expected a number, found \"" + accents.substr(0, 160) + "... (162 bytes)\"");
  // A line break in a value would split one problem over two lines.
  EXPECT_EQ(issues[1].message, "expected a number, found \"a\\nb\\tc\"");
}

TEST(Echo, AHugeKeyIsCutInTheKeyPath) {
  const std::string key(10'000, 'k');
  auto [document, root] = read("? " + key + "\n: 1\n");  // Explicit: a plain key ends at 1024.
  root.finish();
  const auto& issues = document.issues()->issues();
  ASSERT_EQ(issues.size(), 1u);
  const std::string text = issues[0].to_string();
  EXPECT_LT(text.size(), 400u) << text;
  EXPECT_NE(
      text.find("doc.yaml:1:3: " + std::string(160, 'k') + "... (10000 bytes): unknown key \"" +
                std::string(80, 'k') + "... (10000 bytes)\""),
      std::string::npos)
      << text;
}

TEST(ClosestName, NothingIsSuggestedForOrAsAVeryLongWord) {
  // The distance costs |word| x |name|: two 30 kB names took seconds per suggestion.
  const std::string long_name(101, 'a');
  EXPECT_EQ(closest_name(long_name, {long_name}), std::nullopt);
  EXPECT_EQ(closest_name(std::string(100, 'a'), {std::string(100, 'a')}), std::string(100, 'a'));
  EXPECT_EQ(closest_name("a", {long_name}), std::nullopt);
}

}  // namespace
}  // namespace cambio::config
