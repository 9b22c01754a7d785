// Bad input to `cambio` exits 2 with a message that names what and where, never 1 with a
// library's text: numbers on the command line, image files, output directories.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "run_cambio.hpp"

namespace cambio {
namespace {

using testing::run_cambio;

struct Case {
  std::string arguments;
  std::string expected;  ///< A part of the message.
};

void expect_bad_input(const std::vector<Case>& cases) {
  for (const auto& c : cases) {
    const auto result = run_cambio(c.arguments);
    EXPECT_EQ(result.exit_code, 2) << c.arguments << "\n" << result.output;
    EXPECT_NE(result.output.find(c.expected), std::string::npos)
        << c.arguments << ": expected '" << c.expected << "' in\n"
        << result.output;
  }
}

// Every numeric option of every command, each just outside its range or not a number at all.
// Before, --repeats 0 became 5, --repeats 2147483648 ended in vector::reserve (exit 1), --cpu -5
// and --priority 4294967376 (80 after wrapping) were accepted, --duration-s 1e300 ran forever.
TEST(BadInputTest, EveryNumericOptionIsRangeChecked) {
  expect_bad_input({
      {"perception-bench --repeats 0", "'--repeats' expects a whole number in [5, 100000]"},
      {"perception-bench --repeats 2147483648", "got '2147483648'"},
      {"loop-bench --cpu -5", "'--cpu' expects a whole number in [-1, "},
      {"loop-bench --priority 4294967376", "'--priority' expects a whole number in [0, 99]"},
      {"loop-bench --rate-hz 0", "'--rate-hz' expects a number in (0, 100000]"},
      {"loop-bench --rate-hz 0x10", "'--rate-hz' expects a number in (0, 100000]"},
      {"loop-bench --duration-s 1e300", "'--duration-s' expects a number in (0, 36000]"},
      {"loop-bench --duration-s nan", "'--duration-s' expects a number in (0, 36000]"},
      {"sim-bench --seconds 0", "'--seconds' expects a number in (0, 3600]"},
      {"sim-bench --width 8193 --height 480", "'--width' expects a whole number in [16, 8192]"},
      {"sim-bench --width 640 --height 15", "'--height' expects a whole number in [16, 8192]"},
  });
}

}  // namespace
}  // namespace cambio
