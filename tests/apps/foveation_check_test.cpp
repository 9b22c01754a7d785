// foveation_check: a fovea must hold every retina level whose blocks are finer than the
// periphery's pixels. The retina's levels (4 of 16x16 samples, blocks 1, 2, 4 px, then one
// covering the field) and the operators' apron come from the SSM's defaults; the extents are
// worked out here by hand from them.
#include "foveation_check.hpp"

#include <gtest/gtest.h>

#include "cambio/perception/sensory_servo.hpp"

namespace cambio::app {
namespace {

config::CameraConfig eye(int downscale, int fovea_px) {
  config::CameraConfig camera;
  camera.name = "left_eye";
  camera.width_px = 640;
  camera.height_px = 480;
  camera.sim_foveation = {downscale, fovea_px};
  return camera;
}

int apron_of(const perception::SsmConfig& ssm) {
  return perception::SensoryServo(ssm, 640, 480).retina(hal::Eye::kLeft).apron();
}

TEST(FoveationCheck, AFoveaHoldingTheFineLevelsWithTheirApronIsQuiet) {
  const perception::SsmConfig ssm;
  const int apron = apron_of(ssm);
  ASSERT_GT(apron, 0);
  // Downscale 4: levels of 1 and 2 px blocks must fit; level 1 spans (16 + 2 apron) x 2 px.
  EXPECT_TRUE(foveation_warnings(eye(4, (16 + 2 * apron) * 2), ssm).empty());
  EXPECT_TRUE(foveation_warnings(eye(1, 8), ssm).empty()) << "foveation off";
}

TEST(FoveationCheck, ALevelReachingBeyondTheFoveaIsNamed) {
  const perception::SsmConfig ssm;
  const int apron = apron_of(ssm);
  const int level1_px = (16 + 2 * apron) * 2;
  const auto warnings = foveation_warnings(eye(4, level1_px - 2), ssm);
  ASSERT_EQ(warnings.size(), 1U);
  EXPECT_NE(warnings[0].find("cameras.left_eye.sim_foveation.fovea_px"), std::string::npos)
      << warnings[0];
  EXPECT_NE(warnings[0].find("retina level 1 (2 px blocks, " + std::to_string(level1_px) + "x"),
            std::string::npos)
      << warnings[0];
  // Downscale 8 adds the level of 4 px blocks.
  EXPECT_EQ(foveation_warnings(eye(8, level1_px), ssm).size(), 1U);
  EXPECT_EQ(foveation_warnings(eye(8, 16), ssm).size(), 3U);
}

}  // namespace
}  // namespace cambio::app
