// The eyes' views drop geoms outside the frustum and draw the rest nearest first
// (sim/src/view_culling.cpp). What they show must not change: each view is compared with MuJoCo's
// own rendering of the same scene, every geom drawn in MuJoCo's order.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cambio/hal/manual_clock.hpp"
#include "cambio/sim/renderer.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "sim_test_support.hpp"

namespace cambio::sim {
namespace {

struct ViewCase {
  const char* name;
  int width_px, height_px;
  double neck_pan, neck_tilt, eye_tilt, left_pan, right_pan;
};

// The vergence scene (floor, sky planes, textured backdrop, objects on stands) plus markers that
// straddle the edges of the eyes' field with the head straight: a culling test that dropped a
// geom partly in view would lose part of a marker.
config::SceneConfig scene_with_edge_markers() {
  auto scene = sim::testing::load_shipped_scene("vergence");
  const char* yaml =
      "objects:\n"
      "  - {name: m_left, shape: sphere, radius_m: 0.05, xyz_m: [1.0, 0.62, 1.4], rgb: [1, 0, 0]}\n"
      "  - {name: m_right, shape: box, size_m: [0.1, 0.1, 0.1], xyz_m: [1.0, -0.62, 1.4], "
      "rgb: [0, 1, 0]}\n"
      "  - {name: m_top, shape: capsule, radius_m: 0.03, length_m: 0.2, xyz_m: [1.0, 0.0, 1.84], "
      "rgb: [0, 0, 1]}\n"
      "  - {name: m_low, shape: cylinder, radius_m: 0.05, length_m: 0.1, xyz_m: [1.0, 0.0, 0.98], "
      "rgb: [1, 1, 0]}\n"
      "  - {name: behind, shape: sphere, radius_m: 0.2, xyz_m: [-1.0, 0.0, 1.4], rgb: [1, 0, 1]}\n";
  const auto extra = config::load_scene_from_string(yaml, "markers.yaml");
  for (const auto& object : extra.objects) scene.objects.push_back(object);
  return scene;
}

class ViewCullingTest : public ::testing::TestWithParam<ViewCase> {};

TEST_P(ViewCullingTest, EyeViewMatchesMuJoCosUnculledRendering) {
  const ViewCase view = GetParam();
  auto rig = sim::testing::load_shipped_rig();
  sim::testing::make_ideal(rig);
  for (auto& camera : rig.cameras) {
    // The same 60 deg horizontal field at every size, so the markers straddle the edges.
    camera.width_px = view.width_px;
    camera.height_px = view.height_px;
    camera.focal_x_px = camera.focal_y_px = 0.5 * view.width_px / 0.57735026919;
    camera.principal_x_px = 0.5 * (view.width_px - 1);
    camera.principal_y_px = 0.5 * (view.height_px - 1);
  }
  sim::testing::set_initial(rig, "neck_pan", view.neck_pan);
  sim::testing::set_initial(rig, "neck_tilt", view.neck_tilt);
  sim::testing::set_initial(rig, "eye_tilt", view.eye_tilt);
  sim::testing::set_initial(rig, "left_eye_pan", view.left_pan);
  sim::testing::set_initial(rig, "right_eye_pan", view.right_pan);
  hal::ManualClock clock;
  auto sim = sim::testing::make_sim(rig, scene_with_edge_markers(), clock);
  Renderer& renderer = sim->renderer();
  const std::size_t bytes = static_cast<std::size_t>(view.width_px) * view.height_px * 3;
  for (const char* eye : {"left_eye", "right_eye"}) {
    const int camera_id = sim->world().camera_id(eye);
    std::vector<std::uint8_t> culled(bytes), reference(bytes);
    {
      const Renderer::Lease lease(renderer, Renderer::Lease::Mode::kWait);
      ASSERT_TRUE(renderer.render(camera_id, view.width_px, view.height_px, ViewOptions{},
                                  culled.data(), nullptr));
      renderer.render_raw_reference(camera_id, view.width_px, view.height_px, reference.data());
    }
    // Drawing order may only change which of two coincident surfaces wins a depth tie; the
    // scene has none the eyes see, so nearly every pixel is identical.
    std::size_t differing = 0;
    std::size_t marker_pixels = 0;
    for (std::size_t i = 0; i < bytes; i += 3) {
      int worst = 0;
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(culled[i + c] - reference[i + c]));
      differing += worst > 8 ? 1 : 0;
      const int r = reference[i], g = reference[i + 1], b = reference[i + 2];
      // The left edge's red marker (left eye) or the right edge's green one (right eye).
      marker_pixels += (r > 150 && g < 60 && b < 60) || (g > 150 && r < 60 && b < 60) ? 1 : 0;
    }
    EXPECT_LE(differing, bytes / 3 / 1000) << view.name << ", " << eye << ": " << differing
                                           << " pixels differ from MuJoCo's unculled view";
    if (std::string(view.name) == "straight") {
      EXPECT_GT(marker_pixels, 0U) << eye
                                   << ": no edge marker in view; the test "
                                      "would not see a marker wrongly culled";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(HeadPoses, ViewCullingTest,
                         ::testing::Values(ViewCase{"straight", 320, 240, 0, 0, 0, 0, 0},
                                           ViewCase{"wide", 320, 160, 0, 0, 0, 0, 0},
                                           ViewCase{"turned", 320, 240, 0.6, -0.3, 0.2, -0.3, 0.4},
                                           ViewCase{"down", 160, 120, -0.4, 0.5, 0.3, 0.2, -0.1}),
                         [](const ::testing::TestParamInfo<ViewCase>& param) {
                           return std::string(param.param.name);
                         });

}  // namespace
}  // namespace cambio::sim
