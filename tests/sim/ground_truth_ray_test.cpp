// GroundTruth's ray queries against closed-form geometry: a sphere, an axis-aligned box and the
// floor at known places, with the robot's head between some rays and the scene.

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "cambio/hal/manual_clock.hpp"
#include "sim_test_support.hpp"

namespace cambio::sim {
namespace {

constexpr double kRadius_m = 0.10;
const Eigen::Vector3d kBallCentre_W(1.0, 0.06, 1.40);
constexpr double kBoxNearFace_x_m = 1.9;  // The box spans x 1.9 .. 2.1, y -0.1 .. 0.3.

config::SceneConfig ray_scene() {
  return config::load_scene_from_string(R"(
world: {floor: true}
objects:
  - {name: ball, shape: sphere, radius_m: 0.10, xyz_m: [1.0, 0.06, 1.40], rgb: [1, 0, 0]}
  - {name: crate, shape: box, size_m: [0.2, 0.4, 0.4], xyz_m: [2.0, 0.1, 1.40], rgb: [0, 0, 1]}
)",
                                        "ray_scene.yaml");
}

class GroundTruthRayTest : public ::testing::Test {
 protected:
  GroundTruthRayTest()
      : sim_(testing::make_sim(testing::load_shipped_rig(), ray_scene(), clock_)),
        truth_(sim_->ground_truth()) {}

  hal::ManualClock clock_;
  std::unique_ptr<SimBackend> sim_;
  GroundTruth& truth_;
};

TEST_F(GroundTruthRayTest, HitsASphereAtTheClosedFormDistance) {
  // A ray at offset b from the centre enters a sphere of radius r at d - sqrt(r^2 - b^2).
  const double b = 0.05;
  const Eigen::Vector3d origin(0.3, kBallCentre_W.y() + b, kBallCentre_W.z());
  const RayHit hit = truth_.cast_ray(origin, Eigen::Vector3d(2.0, 0.0, 0.0));
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.object, "ball");
  const double expected =
      (kBallCentre_W.x() - origin.x()) - std::sqrt(kRadius_m * kRadius_m - b * b);
  EXPECT_NEAR(hit.distance_m, expected, 1e-9);
  EXPECT_NEAR((hit.p_W - kBallCentre_W).norm(), kRadius_m, 1e-9);
  EXPECT_NEAR(hit.p_W.y(), origin.y(), 1e-12);
}

TEST_F(GroundTruthRayTest, SeesThroughTheRobotsOwnHead) {
  // From behind the head through the left eye (at about (0.06, 0.06, 1.40)): the head's geoms
  // would stop the ray at about 1 m; the scene's first surface is the ball's back at 1.9 m.
  const Eigen::Vector3d origin(-1.0, kBallCentre_W.y(), kBallCentre_W.z());
  const RayHit hit = truth_.cast_ray(origin, Eigen::Vector3d::UnitX());
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.object, "ball");
  EXPECT_NEAR(hit.distance_m, 2.0 - kRadius_m, 1e-9);
}

TEST_F(GroundTruthRayTest, PassesThroughAnIgnoredObjectToTheNextSurface) {
  const Eigen::Vector3d origin(0.0, kBallCentre_W.y(), kBallCentre_W.z());
  const RayHit hit = truth_.cast_ray(origin, Eigen::Vector3d::UnitX(), "ball");
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.object, "crate");
  EXPECT_NEAR(hit.distance_m, kBoxNearFace_x_m, 1e-9);
  EXPECT_NEAR(hit.p_W.x(), kBoxNearFace_x_m, 1e-9);
}

TEST_F(GroundTruthRayTest, NamesTheFloorAndReportsAMiss) {
  // Down at 45 degrees from 1.4 m: the floor (z = 0) at 1.4 * sqrt(2).
  const RayHit floor =
      truth_.cast_ray(Eigen::Vector3d(0.0, -1.0, 1.4), Eigen::Vector3d(0.0, -1.0, -1.0));
  ASSERT_TRUE(floor.hit);
  EXPECT_EQ(floor.object, "floor");
  EXPECT_NEAR(floor.distance_m, 1.4 * std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(floor.p_W.z(), 0.0, 1e-9);
  EXPECT_FALSE(
      truth_.cast_ray(Eigen::Vector3d(0.0, -1.0, 1.4), Eigen::Vector3d(0.0, -1.0, -1.0), "floor")
          .hit);
  const RayHit sky = truth_.cast_ray(Eigen::Vector3d(0.0, 0.0, 1.4), Eigen::Vector3d::UnitZ());
  EXPECT_FALSE(sky.hit) << sky.object << " at " << sky.distance_m;
  EXPECT_TRUE(sky.object.empty());
  EXPECT_TRUE(std::isinf(sky.distance_m));
  EXPECT_TRUE(sky.p_W.hasNaN());
}

TEST_F(GroundTruthRayTest, TellsWhetherAnotherObjectBlocksASegment) {
  const Eigen::Vector3d eye(0.08, 0.06, 1.40);
  // The crate's face straight behind the ball: the ball hides it.
  const Eigen::Vector3d behind(kBoxNearFace_x_m, 0.06, 1.40);
  const RayHit blocked = truth_.segment_blocker(eye, behind, "crate");
  ASSERT_TRUE(blocked.hit);
  EXPECT_EQ(blocked.object, "ball");
  EXPECT_NEAR(blocked.distance_m, kBallCentre_W.x() - kRadius_m - eye.x(), 1e-9);
  // The ball's near pole, seen from the eye, on the object it lies on: clear.
  const Eigen::Vector3d pole = kBallCentre_W - Eigen::Vector3d(kRadius_m, 0.0, 0.0);
  EXPECT_FALSE(truth_.segment_blocker(eye, pole, "ball").hit);
  // Without naming it, the point's own surface is within the tolerance: clear too.
  EXPECT_FALSE(truth_.segment_blocker(eye, pole).hit);
  // The far pole is hidden by the ball itself unless the ball is passed through.
  const Eigen::Vector3d far_pole = kBallCentre_W + Eigen::Vector3d(kRadius_m, 0.0, 0.0);
  EXPECT_EQ(truth_.segment_blocker(eye, far_pole).object, "ball");
  // A segment that stops short of every surface.
  EXPECT_FALSE(truth_.segment_blocker(eye, Eigen::Vector3d(0.5, 0.06, 1.40)).hit);
}

TEST_F(GroundTruthRayTest, RefusesDegenerateRaysAndUnknownObjects) {
  EXPECT_THROW(truth_.cast_ray(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()),
               std::invalid_argument);
  EXPECT_THROW(truth_.cast_ray(Eigen::Vector3d::Zero(), Eigen::Vector3d(std::nan(""), 0.0, 0.0)),
               std::invalid_argument);
  EXPECT_THROW(truth_.cast_ray(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), "no_such"),
               std::out_of_range);
}

}  // namespace
}  // namespace cambio::sim
