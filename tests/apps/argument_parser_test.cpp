// apps/argument_parser.*: numbers from the command line are range-checked like config values.
#include "argument_parser.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace cambio::app {
namespace {

ArgumentParser parsed(const std::vector<std::string>& args) {
  ArgumentParser parser("bench", "[--n N] [--x X]");
  parser.option("n", "N", "a count").option("x", "X", "a length").option("out", "DIR", "output");
  EXPECT_TRUE(parser.parse(args));
  return parser;
}

/// The UsageError message of `read`, or "accepted".
template <typename Read>
std::string refusal(Read read) {
  try {
    read();
  } catch (const UsageError& error) {
    return error.what();
  }
  return "accepted";
}

const config::Range kCount = config::Range::closed(5, 1000);

TEST(ArgumentParserTest, WholeNumbersInsideTheRangePass) {
  EXPECT_EQ(parsed({"--n", "5"}).integer("n", 7, kCount, "why"), 5);
  EXPECT_EQ(parsed({"--n=1000"}).integer("n", 7, kCount, "why"), 1000);
  EXPECT_EQ(parsed({}).integer("n", 7, kCount, "why"), 7);
}

// Each of these was accepted before: 0 silently became 5, 2147483648 wrapped to a negative int
// and ended in vector::reserve, 4294967301 wrapped to 5.
TEST(ArgumentParserTest, WholeNumbersOutsideTheRangeOrMalformedAreRefusedWithTheRangeAndWhy) {
  for (const char* text : {"0", "-3", "4", "1001", "2147483648", "4294967301",
                           "99999999999999999999", "1e3", " 7", "7 ", "+", "", "0x10", "seven"}) {
    const std::string message = refusal([&] {
      (void)parsed({"--n", text}).integer("n", 7, kCount, "the reason");
    });
    EXPECT_NE(message.find("bench: option '--n' expects a whole number in [5, 1000]"),
              std::string::npos)
        << text << ": " << message;
    EXPECT_NE(message.find("(the reason)"), std::string::npos) << text << ": " << message;
    EXPECT_NE(message.find("got '" + std::string(text) + "'"), std::string::npos) << message;
  }
}

TEST(ArgumentParserTest, NumbersMustBeFiniteDecimalsInsideTheRange) {
  const config::Range positive{0.0, 10.0, true, false};
  EXPECT_DOUBLE_EQ(parsed({"--x", "2.5"}).number("x", 1.0, positive, "why"), 2.5);
  EXPECT_DOUBLE_EQ(parsed({"--x", "1e1"}).number("x", 1.0, positive, "why"), 10.0);
  for (const char* text : {"0", "-1", "10.001", "nan", "inf", "-inf", "1e300", "1e-400", "0x1p3",
                           " 2", "2 ", "fast"}) {
    const std::string message = refusal([&] {
      (void)parsed({"--x", text}).number("x", 1.0, positive, "the reason");
    });
    EXPECT_NE(message.find("option '--x' expects a number in (0, 10] (the reason), got '" +
                           std::string(text) + "'"),
              std::string::npos)
        << text << ": " << message;
  }
}

}  // namespace
}  // namespace cambio::app
