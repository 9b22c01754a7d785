// `cambio eds check`: exit 0 when the drive fits the group, 1 when it does not (one line per
// problem), 2 for bad input (a malformed EDS with file:line:, an unknown group, bad arguments).
#include <gtest/gtest.h>

#include <string>

#include "run_cambio.hpp"

namespace cambio::testing {
namespace {

const std::string kShipped = "firmware_config/eds/cambio_virtual_drive.eds";
const std::string kFixtures = "tests/drivers/canopen/eds/";

bool says(const CommandResult& result, const std::string& text) {
  return result.output.find(text) != std::string::npos;
}

TEST(EdsCheck, TheShippedEdsFitsTheShippedGroups) {
  for (const char* rig_group : {"--rig pan_tilt --group pan_tilt", "--rig cambio --group head",
                                "--rig firmware_config/rigs/cambio.yaml --group left_arm"}) {
    const CommandResult result = run_cambio("eds check " + kShipped + " " + rig_group);
    EXPECT_EQ(result.exit_code, 0) << rig_group << ":\n" << result.output;
    EXPECT_TRUE(says(result, "fits: ")) << result.output;
  }
}

TEST(EdsCheck, AVendorDriveThatDoesNotFitExitsOneNamingEachProblem) {
  const CommandResult result =
      run_cambio("eds check " + kFixtures + "drivelabs_dl7.eds --rig pan_tilt --group pan_tilt");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  // The six the drive lacks for streaming, and the five homing objects the pan's homing needs.
  EXPECT_TRUE(says(result, "does not fit: 11 problems")) << result.output;
  EXPECT_TRUE(says(result,
                   "  0x6098:00 (not in the EDS), joint pan: not in the EDS; the master "
                   "writes it (homing (CiA 402 mode 6)"))
      << result.output;
  EXPECT_TRUE(says(result, "  0x1017:00 (not in the EDS), joints pan, tilt: not in the EDS"))
      << result.output;
  EXPECT_TRUE(says(result, "0x6502:00 Supported drive modes (line 623), joints pan, tilt:"))
      << result.output;
}

TEST(EdsCheck, ANodeIdSelectsOneJoint) {
  const CommandResult result = run_cambio("eds check " + kFixtures +
                                          "kinetra_kx40.eds --rig pan_tilt --group pan_tilt "
                                          "--node-id 2");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_TRUE(says(result, "1 of 2 joints checked (tilt node 2)")) << result.output;
  EXPECT_FALSE(says(result, "joint pan")) << result.output;
  const CommandResult nobody =
      run_cambio("eds check " + kShipped + " --rig pan_tilt --group pan_tilt --node-id 9");
  EXPECT_EQ(nobody.exit_code, 2) << nobody.output;
}

TEST(EdsCheck, BadInputExitsTwo) {
  const CommandResult malformed =
      run_cambio("eds check " + kFixtures + "malformed.eds --rig pan_tilt --group pan_tilt");
  EXPECT_EQ(malformed.exit_code, 2) << malformed.output;
  EXPECT_TRUE(says(malformed, kFixtures + "malformed.eds:25: [1000] DataType 0x0030: unknown"))
      << malformed.output;
  EXPECT_TRUE(says(malformed, "10 problems in the EDS")) << malformed.output;

  for (const std::string& arguments :
       {"eds check " + kShipped + " --rig pan_tilt --group head",  // Unknown group.
        "eds check " + kShipped + " --group pan_tilt",             // No rig.
        "eds check " + kShipped + " --rig pan_tilt --group pan_tilt --node-id 200",
        std::string("eds check no_such.eds --rig pan_tilt --group pan_tilt"),
        "eds verify " + kShipped, std::string("eds")}) {
    const CommandResult result = run_cambio(arguments);
    EXPECT_EQ(result.exit_code, 2) << arguments << ":\n" << result.output;
  }
  EXPECT_TRUE(says(run_cambio("eds verify x"), "unknown subcommand 'verify'"));
  EXPECT_EQ(run_cambio("eds check --help").exit_code, 0);
}

}  // namespace
}  // namespace cambio::testing
