// GroundTruth's distances against closed-form geometry: a point to a sphere and to a box (in
// front of a face, off a corner, inside), and the right hand's fingers to a wall in front of
// them, where the generated fingertips (mjcf_builder.hpp) put it by the rig's arm lengths.

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "cambio/hal/manual_clock.hpp"
#include "cambio/sim/mjcf_builder.hpp"
#include "sim_test_support.hpp"

namespace cambio::sim {
namespace {

// The right arm at zero points forward from its shoulder at (0, -0.22, 1.05): upper arm 0.30,
// forearm 0.25, wrist to gripper 0.08, then the closed fingertips (the shipped rig's
// touch_sensors.right_hand.fingertip_xy_m).
constexpr double kFingertips_x_m = 0.30 + 0.25 + 0.08 + 0.082;
constexpr double kWallFace_x_m = 0.80;

config::SceneConfig distance_scene() {
  return config::load_scene_from_string(R"(
world: {floor: true}
objects:
  - {name: ball, shape: sphere, radius_m: 0.10, xyz_m: [1.0, 0.06, 1.40], rgb: [1, 0, 0]}
  - {name: crate, shape: box, size_m: [0.2, 0.4, 0.4], xyz_m: [2.0, 0.1, 1.40], rgb: [0, 0, 1]}
  - {name: wall, shape: box, size_m: [0.1, 0.3, 0.3], xyz_m: [0.85, -0.22, 1.05], rgb: [0, 1, 0]}
)",
                                        "distance_scene.yaml");
}

class GroundTruthDistanceTest : public ::testing::Test {
 protected:
  GroundTruthDistanceTest()
      : sim_(testing::make_sim(testing::load_shipped_rig(), distance_scene(), clock_)),
        truth_(sim_->ground_truth()) {}

  hal::ManualClock clock_;
  std::unique_ptr<SimBackend> sim_;
  GroundTruth& truth_;
};

TEST_F(GroundTruthDistanceTest, APointToASphereIsItsDistanceToTheCentreLessTheRadius) {
  const Eigen::Vector3d centre(1.0, 0.06, 1.40);
  EXPECT_NEAR(truth_.distance_to_object_m("ball", centre + Eigen::Vector3d(0.0, 0.3, 0.0)), 0.2,
              1e-12);
  EXPECT_NEAR(truth_.distance_to_object_m("ball", centre), -0.1, 1e-12);
}

TEST_F(GroundTruthDistanceTest, APointToABoxInFrontOffACornerAndInside) {
  // The crate spans x 1.9 .. 2.1, y -0.1 .. 0.3, z 1.2 .. 1.6.
  EXPECT_NEAR(truth_.distance_to_object_m("crate", Eigen::Vector3d(1.8, 0.1, 1.4)), 0.1, 1e-12);
  EXPECT_NEAR(truth_.distance_to_object_m("crate", Eigen::Vector3d(1.8, 0.4, 1.7)),
              std::sqrt(3.0) * 0.1, 1e-12);
  EXPECT_NEAR(truth_.distance_to_object_m("crate", Eigen::Vector3d(2.0, 0.1, 1.4)), -0.1, 1e-12);
  EXPECT_THROW(truth_.distance_to_object_m("nothing", Eigen::Vector3d::Zero()), std::out_of_range);
}

TEST_F(GroundTruthDistanceTest, TheHandsGapToAWallIsWhereItsFingertipsEnd) {
  // The wall's near face at x 0.80 spans the fingertips' y and z: the pads' front corners are
  // the hand's nearest points.
  EXPECT_NEAR(truth_.end_effector_gap_m("right_gripper", "wall"), kWallFace_x_m - kFingertips_x_m,
              1e-9);
  // The left hand points forward 0.44 m to the left of the right one: nowhere near the wall.
  EXPECT_GT(truth_.end_effector_gap_m("left_gripper", "wall"), 0.25);
  EXPECT_THROW(truth_.end_effector_gap_m("right_gripper", "nothing"), std::out_of_range);
  EXPECT_THROW(truth_.end_effector_gap_m("no_link", "wall"), std::out_of_range);
}

TEST(GroundTruthDistance, TheSimBuildsTheFingersTheRigDescribes) {
  // Fingers 2 cm longer (touch_sensors.right_hand.fingertip_xy_m): the hand ends 2 cm nearer
  // the wall.
  config::RigConfig rig = testing::load_shipped_rig();
  ASSERT_EQ(rig.touch_sensors[1].parent, "right_gripper");
  rig.touch_sensors[1].fingertip_x_m += 0.02;
  hal::ManualClock clock;
  const auto sim = testing::make_sim(rig, distance_scene(), clock);
  EXPECT_NEAR(sim->ground_truth().end_effector_gap_m("right_gripper", "wall"),
              kWallFace_x_m - kFingertips_x_m - 0.02, 1e-9);
}

}  // namespace
}  // namespace cambio::sim
