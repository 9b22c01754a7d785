// The eyes' geometry against the pinhole model: projection, metric depth, stereo disparity.
#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "cambio/hal/manual_clock.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "sim_test_support.hpp"

namespace cambio::sim {
namespace {

using testing::Centroid;

// A small red sphere in a grey room (no floor texture to confuse the centroid).
config::SceneConfig marker_scene(const Eigen::Vector3d& p_W, double radius_m) {
  char yaml[512];
  std::snprintf(yaml, sizeof yaml,
                "world: {floor: false, sky_rgb: [0.5, 0.5, 0.55]}\n"
                "objects:\n"
                "  - {name: marker, shape: sphere, radius_m: %.6f, xyz_m: [%.9f, %.9f, %.9f], "
                "rgb: [1, 0, 0]}\n",
                radius_m, p_W.x(), p_W.y(), p_W.z());
  return config::load_scene_from_string(yaml, "marker.yaml");
}

Eigen::Vector2d project(const hal::CameraIntrinsics& k, const Eigen::Isometry3d& X_WC,
                        const Eigen::Vector3d& p_W) {
  const Eigen::Vector3d p_C = X_WC.inverse() * p_W;
  return {k.focal_x_px * p_C.x() / p_C.z() + k.principal_x_px,
          k.focal_y_px * p_C.y() / p_C.z() + k.principal_y_px};
}

struct Pose {
  double neck_pan, neck_tilt, eye_tilt, left_pan, right_pan;
};

class ProjectionTest : public ::testing::TestWithParam<Pose> {};

TEST_P(ProjectionTest, MarkerAppearsWherePinholePredictsInEachEye) {
  const Pose pose = GetParam();
  auto rig = testing::load_shipped_rig();
  testing::make_ideal(rig);
  testing::set_initial(rig, "neck_pan", pose.neck_pan);
  testing::set_initial(rig, "neck_tilt", pose.neck_tilt);
  testing::set_initial(rig, "eye_tilt", pose.eye_tilt);
  testing::set_initial(rig, "left_eye_pan", pose.left_pan);
  testing::set_initial(rig, "right_eye_pan", pose.right_pan);
  // A point off both optical axes, about 1 m away.
  const Eigen::Vector3d p_W(1.05, 0.09, 1.33);
  hal::ManualClock clock;
  auto sim = testing::make_sim(rig, marker_scene(p_W, 0.012), clock);
  auto& backend = *sim;
  backend.activate();
  for (const char* name : {"left_eye", "right_eye"}) {
    auto camera = backend.make_camera(name);
    const auto& k = camera->info().intrinsics;
    hal::Image image(k.width_px, k.height_px, hal::PixelFormat::kRgb8);
    ASSERT_EQ(camera->grab(image), hal::Status::kOk);
    const Centroid seen = testing::red_centroid(image);
    ASSERT_GT(seen.weight, 0.0) << name << ": marker not in view";
    const Eigen::Vector2d expected = project(k, backend.ground_truth().X_WC(name), p_W);
    EXPECT_NEAR(seen.x, expected.x(), 0.5) << name;
    EXPECT_NEAR(seen.y, expected.y(), 0.5) << name;
  }
}

INSTANTIATE_TEST_SUITE_P(HeadPoses, ProjectionTest,
                         ::testing::Values(Pose{0, 0, 0, 0, 0}, Pose{0.05, 0.1, -0.05, 0.08, -0.06},
                                           Pose{-0.04, 0.06, 0.05, 0.02, 0.1}));

TEST(DepthTest, MetricDepthOfAWallOneMetreAheadIsWithinOneMillimetre) {
  auto rig = testing::load_shipped_rig();
  testing::make_ideal(rig);
  // Where the left eye is with every joint at zero, from a first world.
  Eigen::Isometry3d X_WC;
  {
    hal::ManualClock clock;
    X_WC = testing::make_sim(rig, testing::empty_scene(), clock)->ground_truth().X_WC("left_eye");
  }
  // A wall whose front face is exactly 1 m ahead of the eye, square to its optical axis (+x).
  const double face_x = X_WC.translation().x() + 1.0;
  char yaml[256];
  std::snprintf(
      yaml, sizeof yaml,
      "world: {floor: false}\nobjects:\n  - {name: wall, shape: box, size_m: [0.1, 4, 4], "
      "xyz_m: [%.9f, 0, 1.4], rgb: [0.6, 0.6, 0.6]}\n",
      face_x + 0.05);
  hal::ManualClock clock;
  auto backend = testing::make_sim(rig, config::load_scene_from_string(yaml, "wall.yaml"), clock);
  hal::Image rgb;
  std::vector<float> depth_m;
  backend->ground_truth().render("left_eye", 0, 0, ViewOptions{}, rgb, &depth_m);
  const int w = rgb.width_px, h = rgb.height_px;
  for (const auto& [x, y] : {std::pair{w / 2, h / 2}, std::pair{10, 10}, std::pair{w - 11, h - 11},
                             std::pair{w / 4, 3 * h / 4}}) {
    EXPECT_NEAR(depth_m[static_cast<std::size_t>(y * w + x)], 1.0, 1e-3)
        << "pixel " << x << "," << y;
  }
}

TEST(StereoTest, EyesDifferByTheExpectedDisparityForAKnownDepth) {
  auto rig = testing::load_shipped_rig();
  testing::make_ideal(rig);
  Eigen::Isometry3d X_WL, X_WR;
  {
    hal::ManualClock clock;
    auto probe = testing::make_sim(rig, testing::empty_scene(), clock);
    X_WL = probe->ground_truth().X_WC("left_eye");
    X_WR = probe->ground_truth().X_WC("right_eye");
  }
  const double baseline_m = (X_WL.translation() - X_WR.translation()).norm();
  ASSERT_NEAR(baseline_m, rig.stereo->baseline_m, 1e-9);
  for (const double depth_m : {0.6, 1.0, 2.0}) {
    // Straight ahead of the midpoint between the eyes, both eyes parallel.
    const Eigen::Vector3d mid = 0.5 * (X_WL.translation() + X_WR.translation());
    const Eigen::Vector3d p_W = mid + Eigen::Vector3d(depth_m, 0.0, 0.0);
    hal::ManualClock clock;
    auto backend = testing::make_sim(rig, marker_scene(p_W, 0.01 * depth_m), clock);
    backend->activate();
    auto left = backend->make_camera("left_eye");
    auto right = backend->make_camera("right_eye");
    const auto& k = left->info().intrinsics;
    hal::Image left_image(k.width_px, k.height_px, hal::PixelFormat::kRgb8);
    hal::Image right_image(k.width_px, k.height_px, hal::PixelFormat::kRgb8);
    ASSERT_EQ(left->grab(left_image), hal::Status::kOk);
    ASSERT_EQ(right->grab(right_image), hal::Status::kOk);
    const Centroid l = testing::red_centroid(left_image);
    const Centroid r = testing::red_centroid(right_image);
    const double expected = k.focal_x_px * baseline_m / depth_m;
    EXPECT_NEAR(l.x - r.x, expected, 0.5) << "depth " << depth_m;
    EXPECT_NEAR(l.y, r.y, 0.2) << "rows must agree for parallel eyes";
  }
}

TEST(CameraTest, GreyAndRgbFramesAreStampedWithSimTimeAndReportNoNewData) {
  auto rig = testing::load_shipped_rig();
  for (auto& camera : rig.cameras) camera.format = config::PixelFormatConfig::kGrey8;
  hal::ManualClock clock;
  auto sim = testing::make_sim(rig, testing::load_shipped_scene("vergence"), clock);
  auto& backend = *sim;
  auto left = backend.make_camera("left_eye");
  ASSERT_EQ(left->info().format, hal::PixelFormat::kGrey8);
  hal::Image wrong(10, 10, hal::PixelFormat::kGrey8);
  EXPECT_EQ(left->grab(wrong), hal::Status::kRejected);
  hal::Image image(640, 480, hal::PixelFormat::kGrey8);
  EXPECT_EQ(left->grab(image), hal::Status::kNoNewData) << "nothing published before activate()";
  backend.activate();
  ASSERT_EQ(backend.physics().step_once(5'000'000), hal::Status::kOk);
  ASSERT_EQ(left->grab(image), hal::Status::kOk);
  EXPECT_EQ(image.stamp_ns, 5'000'000);
  EXPECT_EQ(image.sequence, 1u);
  EXPECT_EQ(left->grab(image), hal::Status::kNoNewData) << "no physics step since the last grab";
  ASSERT_EQ(backend.physics().step_once(6'000'000), hal::Status::kOk);
  ASSERT_EQ(left->grab(image), hal::Status::kOk);
  EXPECT_EQ(image.stamp_ns, 6'000'000);
  EXPECT_EQ(image.sequence, 2u);
}

}  // namespace
}  // namespace cambio::sim
