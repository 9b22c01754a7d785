// A foveated sim camera (config::SimFoveationConfig): a low-resolution field with a
// full-resolution centre, against the same camera rendering whole frames.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>

#include <gtest/gtest.h>

#include "cambio/hal/manual_clock.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "sim_test_support.hpp"

namespace cambio::sim {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 240;
constexpr int kDownscale = 4;
constexpr int kFoveaPx = 96;

// The vergence scene (textured sphere at the centre, backdrop, floor) and a red marker well
// outside the fovea, in the left eye's lower right quadrant.
config::SceneConfig scene() {
  auto scene = sim::testing::load_shipped_scene("vergence");
  const auto marker = config::load_scene_from_string(
      "objects:\n"
      "  - {name: marker, shape: sphere, radius_m: 0.04, xyz_m: [1.0, -0.25, 1.22], "
      "rgb: [1, 0, 0]}\n",
      "marker.yaml");
  scene.objects.push_back(marker.objects.front());
  return scene;
}

hal::Image grab(bool foveated, hal::PixelFormat format) {
  auto rig = sim::testing::load_shipped_rig();
  sim::testing::make_ideal(rig);
  for (auto& camera : rig.cameras) {
    camera.width_px = kWidth;
    camera.height_px = kHeight;
    camera.focal_x_px = camera.focal_y_px = 277.128;
    camera.principal_x_px = 159.5;
    camera.principal_y_px = 119.5;
    camera.format = format == hal::PixelFormat::kGrey8 ? config::PixelFormatConfig::kGrey8
                                                       : config::PixelFormatConfig::kRgb8;
    camera.sim_foveation =
        foveated ? config::SimFoveationConfig{kDownscale, kFoveaPx} : config::SimFoveationConfig{};
  }
  hal::ManualClock clock;
  auto sim = sim::testing::make_sim(rig, scene(), clock);
  sim->activate();
  auto camera = sim->make_camera("left_eye");
  hal::Image image(kWidth, kHeight, format);
  EXPECT_EQ(camera->grab(image), hal::Status::kOk);
  return image;
}

bool in_fovea(int x, int y) {
  const int x0 = (kWidth - kFoveaPx) / 2;
  const int y0 = (kHeight - kFoveaPx) / 2;
  return x >= x0 && x < x0 + kFoveaPx && y >= y0 && y < y0 + kFoveaPx;
}

TEST(FoveatedCamera, TheFoveaIsTheWholeFramesCentre) {
  for (const auto format : {hal::PixelFormat::kRgb8, hal::PixelFormat::kGrey8}) {
    const hal::Image whole = grab(false, format);
    const hal::Image foveated = grab(true, format);
    const int channels = whole.channels();
    int differing = 0;
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        if (!in_fovea(x, y)) continue;
        for (int c = 0; c < channels; ++c) {
          const int a = whole.row(y)[channels * x + c];
          const int b = foveated.row(y)[channels * x + c];
          differing += std::abs(a - b) > 8 ? 1 : 0;
        }
      }
    }
    // The fovea's frustum is the whole frame's cut to its pixels: the same pixel grid.
    EXPECT_LE(differing, kFoveaPx * kFoveaPx * channels / 1000)
        << differing << " fovea samples differ (channels " << channels << ")";
  }
}

TEST(FoveatedCamera, ThePeripheryIsTheFieldAtAQuarterOfTheResolution) {
  const hal::Image whole = grab(false, hal::PixelFormat::kRgb8);
  const hal::Image foveated = grab(true, hal::PixelFormat::kRgb8);
  // Outside the fovea every downscale x downscale block is one rendered pixel repeated.
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      if (in_fovea(x, y)) continue;
      const int bx = x / kDownscale * kDownscale;
      const int by = y / kDownscale * kDownscale;
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(foveated.row(y)[3 * x + c], foveated.row(by)[3 * bx + c])
            << "pixel (" << x << ", " << y << ")";
      }
    }
  }
  // ...and shows the field where the whole frame does: the marker's centroid within half a
  // periphery pixel.
  const auto expected = sim::testing::red_centroid(whole);
  const auto seen = sim::testing::red_centroid(foveated);
  ASSERT_GT(expected.weight, 50.0) << "the marker is not in view";
  ASSERT_GT(seen.weight, 0.0) << "the marker is missing from the periphery";
  EXPECT_NEAR(seen.x, expected.x, 0.5 * kDownscale);
  EXPECT_NEAR(seen.y, expected.y, 0.5 * kDownscale);
  EXPECT_NEAR(seen.weight, expected.weight, 0.35 * expected.weight);
}

}  // namespace
}  // namespace cambio::sim
