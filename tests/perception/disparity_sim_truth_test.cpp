// Disparity against the simulator's ground truth (issue 4: "when the simulator lands, add
// disparity against its ground-truth depth"). The shipped rig looks at the vergence scene's
// noise-textured sphere; the SSM measures the disparity at a fixation on it, and the truth comes
// from the rendered metric depth at the left fixation pixel back-projected with the left
// camera's true pose and projected into the right camera with its true pose.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../sim/sim_test_support.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/perception/perception_config.hpp"
#include "cambio/perception/sensory_servo.hpp"
#include "cambio/sim/sim_backend.hpp"

namespace cambio::perception {
namespace {

struct StereoShot {
  hal::Image left;
  hal::Image right;
  std::vector<float> left_depth_m;  ///< Along the left optical axis, top row first.
  hal::CameraIntrinsics left_k;
  hal::CameraIntrinsics right_k;
  Eigen::Isometry3d X_WL;  ///< Left camera's optical frame in the world.
  Eigen::Isometry3d X_WR;
  Eigen::Vector3d p_W_sphere;
};

/// One frame of both eyes of the shipped rig in the shipped vergence scene, every joint ideal
/// (no servo noise), the eyes panned to the given angles, images with the given noise.
StereoShot shoot(double left_pan_rad, double right_pan_rad, double image_noise_std) {
  auto rig = sim::testing::load_shipped_rig();
  sim::testing::make_ideal(rig);
  for (auto& camera : rig.cameras) camera.image_noise_std = image_noise_std;
  sim::testing::set_initial(rig, "left_eye_pan", left_pan_rad);
  sim::testing::set_initial(rig, "right_eye_pan", right_pan_rad);
  hal::ManualClock clock;
  auto backend =
      sim::testing::make_sim(rig, sim::testing::load_shipped_scene("vergence"), clock, 11);
  backend->activate();
  auto left = backend->make_camera("left_eye");
  auto right = backend->make_camera("right_eye");
  StereoShot shot;
  shot.left_k = left->info().intrinsics;
  shot.right_k = right->info().intrinsics;
  shot.left.resize(shot.left_k.width_px, shot.left_k.height_px, left->info().format);
  shot.right.resize(shot.right_k.width_px, shot.right_k.height_px, right->info().format);
  EXPECT_EQ(left->grab(shot.left), hal::Status::kOk);
  EXPECT_EQ(right->grab(shot.right), hal::Status::kOk);
  hal::Image rgb;
  auto& truth = backend->ground_truth();
  truth.render("left_eye", 0, 0, sim::ViewOptions{}, rgb, &shot.left_depth_m);
  shot.X_WL = truth.X_WC("left_eye");
  shot.X_WR = truth.X_WC("right_eye");
  shot.p_W_sphere = truth.X_WO("textured_sphere").translation();
  return shot;
}

Eigen::Vector2d project(const hal::CameraIntrinsics& k, const Eigen::Isometry3d& X_WC,
                        const Eigen::Vector3d& p_W) {
  const Eigen::Vector3d p_C = X_WC.inverse() * p_W;
  return {k.focal_x_px * p_C.x() / p_C.z() + k.principal_x_px,
          k.focal_y_px * p_C.y() / p_C.z() + k.principal_y_px};
}

/// The scene point seen at the centre of left pixel `p` (pixel centres at integer coordinates,
/// as the retina and the sim's principal point (w - 1) / 2 both take them), in the world.
Eigen::Vector3d seen_at(const StereoShot& shot, PixelPoint p) {
  const hal::CameraIntrinsics& k = shot.left_k;
  const double z = shot.left_depth_m[static_cast<std::size_t>(p.y * k.width_px + p.x)];
  const Eigen::Vector3d p_C((p.x - k.principal_x_px) * z / k.focal_x_px,
                            (p.y - k.principal_y_px) * z / k.focal_y_px, z);
  return shot.X_WL * p_C;
}

struct Measurement {
  DisparityResult result;
  double predicted_px = 0.0;
  double vertical_px = 0.0;  ///< Vertical disparity of the point at the right fixation's row.
};

/// Runs the SSM once with the given fixations; the truth is the disparity the issue defines,
/// relative to each retina's fixation: (x_left - fl.x) - (x_right - fr.x) with x_left = fl.x.
Measurement measure(const SsmConfig& config, const StereoShot& shot, PixelPoint fl, PixelPoint fr) {
  SensoryServo servo(config, shot.left.width_px, shot.left.height_px);
  SsmFrame frame = servo.make_frame();
  FeatureRequest request;
  request.maps = 0;
  request.motion = false;
  request.moments = false;
  EXPECT_EQ(servo.process(shot.left, shot.right, fl, fr, request, frame), hal::Status::kOk);
  const Eigen::Vector2d in_right = project(shot.right_k, shot.X_WR, seen_at(shot, fl));
  return {frame.summary.disparity, fr.x - in_right.x(), fr.y - in_right.y()};
}

SsmConfig paper_config() {
  SsmConfig config;
  config.motion.enabled = false;
  config.moments.enabled = false;
  return config;
}

PixelPoint rounded(const Eigen::Vector2d& p) {
  return {static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y()))};
}

void report(const char* what, double noise, PixelPoint fl, const Measurement& m) {
  std::printf(
      "[ sim truth ] %s noise %.1f fixation (%d, %d): measured %+.3f px (level %d, "
      "confidence %.2f), predicted %+.3f px, error %+.3f px, vertical %+.3f px\n",
      what, noise, fl.x, fl.y, m.result.disparity_px, m.result.level, m.result.confidence,
      m.predicted_px, m.result.disparity_px - m.predicted_px, m.vertical_px);
  for (int k = m.result.levels - 1; k >= 0; --k) {
    const LevelDisparity& level = m.result.per_level[static_cast<std::size_t>(k)];
    std::printf(
        "[ sim truth ]   level %d (x%d): searched %d valid %d edge %d moved windows %d "
        "range [%d, %d] disparity %+.3f confidence %.2f peak %.2f texture %.1f\n",
        k, level.scale_px, level.searched, level.valid, level.at_range_edge, level.moved_windows,
        level.search_min_px, level.search_max_px, level.disparity_px, level.confidence,
        level.peak_score, level.texture_rms);
  }
}

constexpr double kLeftPanRad = 4.764 * std::numbers::pi / 180.0;  // Onto the sphere.
constexpr double kVergedRightPanRad = 11.6 * std::numbers::pi / 180.0;
// Tolerances, from the measured figures (printed by each case). Rows aligned to within 0.25 px:
// errors up to 0.19 px without noise and 0.2 px with noise 3 (the renderer point-samples the
// texture without anti-aliasing, and the sphere is slanted and curved under the 9 x 9 window),
// so 0.25 px, which still fails a half-pixel convention error. The search is horizontal only:
// with integer fixations the right window's row can be up to 0.5 px off the true vertical
// disparity (verged eyes, points off the horizon), and the oriented texture then biases the
// horizontal match (0.29 px at 0.36 px vertical); there the bound is 0.4 px.
constexpr double kTolerancePx = 0.25;
constexpr double kRowsAlignedPx = 0.25;
constexpr double kToleranceMisalignedPx = 0.4;

struct Case {
  double right_pan_rad;
  double image_noise_std;
};

class SimTruth : public ::testing::TestWithParam<Case> {};

// The left eye fixates the sphere as the main job starts; the right eye is parallel to it or
// verged near it. Right fixations a few pixels off the true correspondence give residual
// vergence errors the fovea measures, sub-pixel parts included, at five points on the sphere.
TEST_P(SimTruth, FoveaMatchesTheDisparityPredictedFromTrueDepthAndPoses) {
  const Case c = GetParam();
  const StereoShot shot = shoot(kLeftPanRad, c.right_pan_rad, c.image_noise_std);
  const PixelPoint on_sphere = rounded(project(shot.left_k, shot.X_WL, shot.p_W_sphere));
  double worst = 0.0;
  for (const PixelPoint fl : {on_sphere, PixelPoint{on_sphere.x + 17, on_sphere.y - 11},
                              PixelPoint{on_sphere.x - 20, on_sphere.y + 14},
                              PixelPoint{on_sphere.x + 25, on_sphere.y + 9},
                              PixelPoint{on_sphere.x - 8, on_sphere.y - 24}}) {
    const PixelPoint match = rounded(project(shot.right_k, shot.X_WR, seen_at(shot, fl)));
    for (const int residual : {0, 2, -3}) {
      const PixelPoint fr{match.x + residual, match.y};
      const Measurement m = measure(paper_config(), shot, fl, fr);
      report("fovea", c.image_noise_std, fl, m);
      ASSERT_TRUE(m.result.valid);
      EXPECT_EQ(m.result.level, 0);
      EXPECT_GT(m.result.confidence, 0.5f);
      worst = std::max(worst, std::abs(m.result.disparity_px - m.predicted_px));
      const double tolerance =
          std::abs(m.vertical_px) <= kRowsAlignedPx ? kTolerancePx : kToleranceMisalignedPx;
      EXPECT_NEAR(m.result.disparity_px, m.predicted_px, tolerance)
          << "fixation " << fl.x << ", " << fl.y << " residual " << residual;
    }
  }
  std::printf("[ sim truth ] right pan %.3f rad, noise %.1f: worst error %.3f px\n",
              c.right_pan_rad, c.image_noise_std, worst);
}

INSTANTIATE_TEST_SUITE_P(EyesAndNoise, SimTruth,
                         ::testing::Values(Case{kLeftPanRad, 0.0}, Case{kLeftPanRad, 3.0},
                                           Case{kVergedRightPanRad, 0.0},
                                           Case{kVergedRightPanRad, 3.0}));

TEST(SimTruthCoarseToFine, ParallelStartOfTheMainJobIsMeasuredInTheFovea) {
  // Both eyes panned 4.764 deg (the main job's start), fixations at the image centres: the
  // vergence error is the full ~68 px; the experiment's SSM config must find it.
  const SsmConfig config =
      load_ssm_config(config::find_shipped_config("perception/vergence.yaml"), {});
  for (const double noise : {0.0, 3.0}) {
    const StereoShot shot = shoot(kLeftPanRad, kLeftPanRad, noise);
    const PixelPoint centre{shot.left.width_px / 2, shot.left.height_px / 2};
    const Measurement m = measure(config, shot, centre, centre);
    report("parallel", noise, centre, m);
    ASSERT_TRUE(m.result.valid);
    EXPECT_NEAR(m.result.disparity_px, m.predicted_px, kTolerancePx * (1 << m.result.level));
  }
}

}  // namespace
}  // namespace cambio::perception
