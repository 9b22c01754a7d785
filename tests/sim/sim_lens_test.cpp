// A sim camera with a lens in its rig entry sees through it: a marker appears where OpenCV's
// cv::projectPoints (the plumb-bob model, a peer implementation) puts it, not where the pinhole
// does; a lens model that folds over inside the image is refused with the camera named.
#include <array>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "cambio/config/config_error.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "sim_test_support.hpp"

namespace cambio::sim {
namespace {

using testing::Centroid;

config::SceneConfig markers_scene(const std::vector<Eigen::Vector3d>& points_W) {
  std::string yaml = "world: {floor: false, sky_rgb: [0.5, 0.5, 0.55]}\nobjects:\n";
  for (std::size_t i = 0; i < points_W.size(); ++i) {
    char line[256];
    std::snprintf(line, sizeof line,
                  "  - {name: marker_%zu, shape: sphere, radius_m: 0.010, xyz_m: [%.9f, %.9f, "
                  "%.9f], rgb: [1, 0, 0]}\n",
                  i, points_W[i].x(), points_W[i].y(), points_W[i].z());
    yaml += line;
  }
  return config::load_scene_from_string(yaml, "markers.yaml");
}

/// A wide-angle USB camera's lens (barrel), as calibrate stereo finds on OpenCV's sample views.
hal::PlumbBobDistortion barrel() {
  return {-0.28, 0.07, 0.001, -0.0005, 0.0};
}

cv::Point2d project(const hal::CameraInfo& info, const Eigen::Isometry3d& X_WC,
                    const Eigen::Vector3d& p_W, bool through_lens) {
  const Eigen::Vector3d p_C = X_WC.inverse() * p_W;
  const hal::CameraIntrinsics& k = info.intrinsics;
  const cv::Matx33d K(k.focal_x_px, 0, k.principal_x_px, 0, k.focal_y_px, k.principal_y_px, 0, 0,
                      1);
  std::array<double, 5> d{};
  if (through_lens) d = info.distortion.opencv_order();
  std::vector<cv::Point2d> projected;
  cv::projectPoints(std::vector<cv::Point3d>{{p_C.x(), p_C.y(), p_C.z()}}, cv::Vec3d(0, 0, 0),
                    cv::Vec3d(0, 0, 0), K, std::vector<double>(d.begin(), d.end()), projected);
  return projected[0];
}

TEST(SimLens, AMarkerAppearsWhereTheLensModelPutsIt) {
  auto rig = testing::load_shipped_rig();
  testing::make_ideal(rig);
  for (auto& camera : rig.cameras) camera.distortion = barrel();
  hal::ManualClock clock;
  // Where the left eye is with every joint at zero, from a first world.
  Eigen::Isometry3d X_WC;
  {
    auto probe = testing::make_sim(rig, testing::empty_scene(), clock);
    X_WC = probe->ground_truth().X_WC("left_eye");
  }
  // One marker at a time, about 1 m ahead: the centre, and towards each corner, where the lens
  // moves points by tens of pixels.
  const std::vector<std::array<double, 2>> directions = {
      {0.0, 0.0}, {0.38, 0.27}, {-0.40, 0.25}, {0.35, -0.28}, {-0.15, -0.30}};
  for (const auto& [x, y] : directions) {
    const Eigen::Vector3d p_W = X_WC * Eigen::Vector3d(x, y, 1.0);
    auto sim = testing::make_sim(rig, markers_scene({p_W}), clock);
    sim->activate();
    auto camera = sim->make_camera("left_eye");
    const hal::CameraInfo& info = camera->info();
    hal::Image image(info.intrinsics.width_px, info.intrinsics.height_px, hal::PixelFormat::kRgb8);
    ASSERT_EQ(camera->grab(image), hal::Status::kOk);
    const Centroid seen = testing::red_centroid(image);
    ASSERT_GT(seen.weight, 0.0) << "marker at (" << x << ", " << y << ") not in view";
    const cv::Point2d lens = project(info, X_WC, p_W, true);
    const cv::Point2d pinhole = project(info, X_WC, p_W, false);
    std::printf(
        "marker (%5.2f, %5.2f): seen (%7.2f, %7.2f), through the lens (%7.2f, %7.2f), "
        "pinhole (%7.2f, %7.2f)\n",
        x, y, seen.x, seen.y, lens.x, lens.y, pinhole.x, pinhole.y);
    EXPECT_NEAR(seen.x, lens.x, 0.5);
    EXPECT_NEAR(seen.y, lens.y, 0.5);
    if (x != 0.0) {
      EXPECT_GT(std::hypot(lens.x - pinhole.x, lens.y - pinhole.y), 5.0)
          << "the test cannot tell the lens";
    }
  }
}

double mean_difference(const hal::Image& a, const hal::Image& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    sum += std::abs(static_cast<int>(a.pixels[i]) - static_cast<int>(b.pixels[i]));
  }
  return sum / static_cast<double>(a.pixels.size());
}

// What a run's key frames show of a lens camera is what the camera grabbed, not the pinhole view.
TEST(SimLens, GroundTruthRendersAsTheCameraSeesThroughItsLens) {
  auto rig = testing::load_shipped_rig();
  testing::make_ideal(rig);
  for (auto& camera : rig.cameras) camera.distortion = barrel();
  hal::ManualClock clock;
  auto sim = testing::make_sim(rig, testing::load_shipped_scene("vergence"), clock);
  sim->activate();
  auto camera = sim->make_camera("left_eye");
  const hal::CameraInfo& info = camera->info();
  hal::Image grabbed(info.intrinsics.width_px, info.intrinsics.height_px, hal::PixelFormat::kRgb8);
  ASSERT_EQ(camera->grab(grabbed), hal::Status::kOk);
  hal::Image as_seen;
  sim->ground_truth().render_as_seen("left_eye", as_seen);
  hal::Image pinhole;
  sim->ground_truth().render("left_eye", 0, 0, ViewOptions{}, pinhole, nullptr);
  ASSERT_EQ(as_seen.width_px, grabbed.width_px);
  ASSERT_EQ(as_seen.height_px, grabbed.height_px);
  const double same = mean_difference(as_seen, grabbed);
  const double lens = mean_difference(pinhole, grabbed);
  std::printf("mean |render_as_seen - grab| %.3f, |pinhole - grab| %.3f grey levels\n", same, lens);
  EXPECT_LT(same, 0.01);
  EXPECT_GT(lens, 5.0) << "the test cannot tell the lens";
}

TEST(SimLens, ALensThatFoldsOverInsideTheImageIsRefused) {
  auto rig = testing::load_shipped_rig();
  rig.cameras.front().distortion.k1 = -2.5;  // Turns back on itself well inside the frame.
  hal::ManualClock clock;
  try {
    auto sim = testing::make_sim(rig, testing::empty_scene(), clock);
    FAIL() << "a folding lens was accepted";
  } catch (const config::ConfigError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("cameras." + rig.cameras.front().name + ".distortion"), std::string::npos)
        << what;
    EXPECT_NE(what.find("folds over"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace cambio::sim
