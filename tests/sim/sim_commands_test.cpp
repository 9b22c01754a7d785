// `cambio render` and `cambio sim-bench` end to end, through the built program.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "../apps/run_cambio.hpp"
#include "../scoped_environment_variable.hpp"
#include "cambio/config/shipped_config.hpp"

namespace cambio::sim {
namespace {

using cambio::testing::run_cambio;

std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::path(CAMBIO_BINARY_DIR) / "test_output" / name;
  std::filesystem::remove_all(dir);
  return dir;
}

TEST(RenderCommandTest, WritesTheEyesDepthAndOverviewForAPose) {
  const auto out = fresh_dir("render");
  const cambio::testing::ScopedEnvironmentVariable surfaceless("CAMBIO_EGL_DEVICE", "surfaceless");
  const auto result = run_cambio("render --config cambio --scene vergence --out '" + out.string() +
                                 "' --set joints.left_eye_pan=0.085 --pose right_eye_pan=12deg");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("\nrenderer: "), std::string::npos) << result.output;
  EXPECT_NE(result.output.find(", on Mesa surfaceless\n"), std::string::npos) << result.output;
  for (const char* name : {"left.png", "right.png", "depth_left.png", "overview.png"}) {
    EXPECT_TRUE(std::filesystem::exists(out / name)) << name;
  }
  const cv::Mat left = cv::imread((out / "left.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(left.cols, 640);
  EXPECT_EQ(left.rows, 480);
  EXPECT_EQ(left.channels(), 3);
  const cv::Mat depth = cv::imread((out / "depth_left.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(depth.type(), CV_16UC1);
  // The textured sphere, verged on, sits about 0.95 m ahead of the left eye.
  const auto centre_mm = depth.at<std::uint16_t>(240, 320);
  EXPECT_GT(centre_mm, 800);
  EXPECT_LT(centre_mm, 1000);
}

TEST(RenderCommandTest, RigOverridesAndPosesAreToldApart) {
  const auto out = fresh_dir("render_override");
  // A rig key path (three components) overrides the rig: here an off-centre principal point,
  // which the sim refuses at config time.
  auto result = run_cambio("render --scene vergence --out '" + out.string() +
                           "' --set cameras.left_eye.principal_point_px=[300,200]");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("principal_point_px"), std::string::npos) << result.output;
  result = run_cambio("render --scene vergence --out '" + out.string() +
                      "' --set joints.left_eye_pan=2");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("outside its limits"), std::string::npos) << result.output;
  result = run_cambio("render --scene vergence --out '" + out.string() + "' --set joints.nope=0.1");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("no joint named 'nope'"), std::string::npos) << result.output;
}

TEST(RenderCommandTest, BadSceneIsRefusedWithFileLineColumn) {
  const auto dir = fresh_dir("bad_scene");
  std::filesystem::create_directories(dir);
  const auto scene = dir / "bad.yaml";
  FILE* file = std::fopen(scene.c_str(), "w");
  ASSERT_NE(file, nullptr);
  std::fputs("objects:\n  - {name: a, shape: pyramid, xyz_m: [1, 0, 1]}\n", file);
  std::fclose(file);
  const auto out = dir / "out";
  const auto result =
      run_cambio("render --scene '" + scene.string() + "' --out '" + out.string() + "'");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("bad.yaml:2:"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(out / "left.png"));
}

// The vergence scene under a name with a quote and a backslash: names are user text, and the
// JSON must stay valid whatever they hold.
TEST(SimBenchCommandTest, PrintsTheFiguresAsJson) {
  const auto dir = fresh_dir("sim_bench");
  std::filesystem::create_directories(dir);
  const std::string name = "quote \" and backslash \\ scene";
  std::ifstream shipped(config::find_shipped_config("scenes/vergence.yaml"));
  std::string yaml((std::istreambuf_iterator<char>(shipped)), std::istreambuf_iterator<char>());
  const std::string shipped_name = "  name: vergence\n";
  ASSERT_NE(yaml.find(shipped_name), std::string::npos);
  yaml.replace(yaml.find(shipped_name), shipped_name.size(), "  name: '" + name + "'\n");
  const auto scene = dir / "renamed.yaml";
  std::ofstream(scene) << yaml;

  const auto result = run_cambio("sim-bench --json --width 160 --height 120 --seconds 0.4 " +
                                     std::string("--camera-scene '") + scene.string() + "'",
                                 cambio::testing::Capture::kStdout);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto figures = nlohmann::json::parse(result.output, nullptr, /*allow_exceptions=*/false);
  ASSERT_FALSE(figures.is_discarded()) << "not JSON:\n" << result.output;
  EXPECT_EQ(figures["camera_scene"], name);
  EXPECT_EQ(figures["width"], 160);
  EXPECT_EQ(figures["height"], 120);
  for (const char* key : {"physics_steps_per_s", "camera_stereo_fps", "raw_mujoco_stereo_fps"}) {
    EXPECT_TRUE(figures[key].is_number()) << key << " in " << result.output;
  }
  // What rendered, and what there was to render on.
  for (const char* key : {"egl_platform", "gl_renderer", "gl_vendor"}) {
    EXPECT_TRUE(figures[key].is_string()) << key << " in " << result.output;
  }
  EXPECT_TRUE(figures["egl_fallback_reason"].is_string() ||
              figures["egl_fallback_reason"].is_null());
  ASSERT_TRUE(figures["egl_devices"].is_array()) << result.output;
  ASSERT_FALSE(figures["egl_devices"].empty()) << "Mesa lists llvmpipe as a device";
  for (const auto& device : figures["egl_devices"]) {
    EXPECT_TRUE(device["index"].is_number_integer()) << device;
    EXPECT_TRUE(device["software"].is_boolean()) << device;
    EXPECT_TRUE(device["drm_device_file"].is_string() || device["drm_device_file"].is_null());
    EXPECT_TRUE(device["drm_render_node"].is_string() || device["drm_render_node"].is_null());
  }
}

// A render device the machine does not have stops the command before anything renders, exit 2,
// naming the key and the devices there are; CAMBIO_EGL_DEVICE is checked the same way.
TEST(RenderCommandTest, AnAbsentRenderDeviceIsBadInput) {
  const auto out = fresh_dir("render_absent_device");
  auto result =
      run_cambio("render --scene vergence --out '" + out.string() + "' --set sim.render_device=99");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("sim.render_device: expected an EGL device index in [0, "),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("(devices: device 0: "), std::string::npos) << result.output;
  {
    const cambio::testing::ScopedEnvironmentVariable variable("CAMBIO_EGL_DEVICE", "gpu");
    result = run_cambio("render --scene vergence --out '" + out.string() + "'");
  }
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("environment: CAMBIO_EGL_DEVICE: expected auto, surfaceless or "
                               "an EGL device index (0, 1, ...), found \"gpu\""),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(std::filesystem::exists(out / "left.png"));
}

}  // namespace
}  // namespace cambio::sim
