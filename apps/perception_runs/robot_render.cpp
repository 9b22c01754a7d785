#include "robot_render.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <memory>
#include <utility>
#include <vector>

#include "cambio/config/hardware_description.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "image_files.hpp"

namespace cambio::app {

namespace {

constexpr int kOverviewWidthPx = 1280;
constexpr int kOverviewHeightPx = 960;

std::vector<std::uint8_t> depth_mm_png(const std::vector<float>& depth_m, int width, int height) {
  std::vector<std::uint16_t> millimetres(depth_m.size());
  std::transform(depth_m.begin(), depth_m.end(), millimetres.begin(), [](float metres) {
    return static_cast<std::uint16_t>(std::clamp(std::lround(metres * 1000.0f), 0L, 65535L));
  });
  return encode_png16(millimetres, width, height);
}

/// The sim backend, its renderer made now, not at the first camera: the renderer refuses
/// cameras larger than it can draw. Null (the issues printed) when the sim cannot build it.
std::unique_ptr<sim::SimBackend> make_backend_or_report(const RenderOptions& options,
                                                        hal::Clock& clock) {
  sim::MjcfOptions mjcf_options;
  mjcf_options.offscreen_width_px = kOverviewWidthPx;
  mjcf_options.offscreen_height_px = kOverviewHeightPx;
  std::unique_ptr<sim::SimBackend> backend;
  try {
    backend = std::make_unique<sim::SimBackend>(options.rig, options.scene,
                                                config::hardware_description(options.rig),
                                                hal::BackendContext{&clock}, mjcf_options);
    (void)backend->renderer();
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return nullptr;
  }
  return backend;
}

void write_mjcf(sim::SimBackend& backend, const std::string& path) {
  std::ofstream mjcf(path);
  mjcf << backend.world().mjcf();
  mjcf.close();
  if (mjcf.fail()) throw OutputError("--mjcf " + path + ": could not write it");
}

/// The camera of each view and its file's stem: the stereo pair as left and right, or else every
/// camera under its own name.
std::vector<std::pair<std::string, std::string>> eye_views(const config::RigConfig& rig) {
  std::vector<std::pair<std::string, std::string>> views;
  if (rig.stereo) {
    views = {{rig.stereo->left_camera, "left"}, {rig.stereo->right_camera, "right"}};
  } else {
    for (const auto& camera : rig.cameras) views.emplace_back(camera.name, camera.name);
  }
  return views;
}

/// The eyes through the HAL camera pipeline, exactly what perception would receive. False (the
/// reason printed) when a camera fails.
bool stage_eye_views(sim::SimBackend& backend,
                     const std::vector<std::pair<std::string, std::string>>& views,
                     OutputDirectory& out) {
  for (const auto& [camera_name, stem] : views) {
    auto camera = backend.make_camera(camera_name);
    const auto& info = camera->info();
    hal::Image image(info.intrinsics.width_px, info.intrinsics.height_px, info.format);
    const hal::Status status = camera->grab(image);
    if (status != hal::Status::kOk) {
      std::cerr << "cambio render: camera " << camera_name << " returned " << hal::to_string(status)
                << "\n";
      return false;
    }
    out.stage(stem + ".png", encode_png(image));
  }
  return true;
}

/// Ground-truth depth of `camera_name` (the left or only eye), in millimetres.
void stage_depth(sim::SimBackend& backend, const std::string& camera_name, const std::string& stem,
                 OutputDirectory& out) {
  hal::Image rgb;
  std::vector<float> depth_m;
  backend.ground_truth().render(camera_name, 0, 0, sim::ViewOptions{}, rgb, &depth_m);
  out.stage(stem + ".png", depth_mm_png(depth_m, rgb.width_px, rgb.height_px));
}

void stage_overview(sim::SimBackend& backend, bool shadows, OutputDirectory& out) {
  sim::ViewOptions view;
  view.shadows = shadows;
  view.show_head = true;
  view.skybox = true;
  view.trilinear_textures = true;
  hal::Image overview;
  backend.ground_truth().render(sim::kOverviewCameraName, kOverviewWidthPx, kOverviewHeightPx, view,
                                overview, nullptr);
  out.stage("overview.png", encode_png(overview));
}

}  // namespace

int render_robot(const RenderOptions& options, OutputDirectory& out) {
  const config::RigConfig& rig = options.rig;
  const auto started = std::chrono::steady_clock::now();
  // Nothing runs in time here: the backend gets a clock that stays at zero.
  hal::ManualClock clock;
  const std::unique_ptr<sim::SimBackend> backend = make_backend_or_report(options, clock);
  if (!backend) return kExitBadInput;
  if (options.mjcf_path) write_mjcf(*backend, *options.mjcf_path);
  // The pose is the initial state: render it as it is, without letting gravity act first.
  backend->activate();
  const auto views = eye_views(rig);
  if (!stage_eye_views(*backend, views, out)) return kExitFailure;
  if (!views.empty()) {
    const std::string& camera_name = views.front().first;
    stage_depth(*backend, camera_name, rig.stereo ? "depth_left" : "depth_" + camera_name, out);
  }
  stage_overview(*backend, options.shadows, out);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::cout << "rendered rig " << rig.name << " in scene " << options.scene.name << " in "
            << static_cast<int>(seconds * 1000) << " ms\n"
            << "renderer: " << backend->renderer().description().summary() << "\n";
  out.commit();
  for (const auto& name : out.files()) std::cout << "  " << (out.path() / name).string() << "\n";
  return kExitOk;
}

}  // namespace cambio::app
