// `cambio sim-bench [--json] [--width W --height H]`: in one run, the sim's physics steps per
// second for the full robot, the stereo frames per second of its camera pipeline (render, read
// back, flip, convert, noise: what Camera::grab does), and, as the reference, a raw MuJoCo
// render-and-read loop of the same scene at the same resolution on the same GL context.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "argument_parser.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/sim/egl_devices.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "json_output.hpp"
#include "renderer_report.hpp"

namespace cambio::app {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Every sim group of the rig, commanded along slow sines inside the joints' limits, so the
/// physics step works with moving arms and contacts, not a robot at rest.
struct Exerciser {
  std::vector<std::unique_ptr<hal::JointGroup>> groups;
  std::vector<std::vector<hal::JointCommand>> commands;

  void command(double t_s) {
    for (std::size_t g = 0; g < groups.size(); ++g) {
      const auto& info = groups[g]->info();
      for (std::size_t k = 0; k < info.joints.size(); ++k) {
        const auto& limits = info.limits[k];
        const double middle = 0.5 * (limits.min_position_rad + limits.max_position_rad);
        const double half = 0.3 * (limits.max_position_rad - limits.min_position_rad);
        commands[g][k] = {hal::CommandMode::kPosition,
                          middle + half * std::sin(0.7 * t_s + static_cast<double>(k))};
      }
      (void)groups[g]->write(commands[g]);
    }
  }
};

}  // namespace

int run_sim_bench_command(std::span<const std::string> args) {
  ArgumentParser parser("sim-bench", "measure the sim's physics and camera throughput");
  parser.option("config", "RIG", "rig file or shipped rig name (default: cambio)")
      .option("scene", "SCENE", "scene for the physics figure (default: table: arms, contacts)")
      .option("camera-scene", "SCENE", "scene for the camera figures (default: vergence)")
      .option("width", "W",
              "eye image width in pixels, 16 to " + std::to_string(sim::kMaxCameraSidePx) +
                  " (default: the rig's)")
      .option("height", "H",
              "eye image height in pixels, 16 to " + std::to_string(sim::kMaxCameraSidePx) +
                  " (default: the rig's)")
      .option("seconds", "S", "wall time per measurement, up to 3600 (default 2)")
      .flag("json", "print one JSON object instead of a table");
  if (!parser.parse(args)) return kExitOk;
  const double seconds = parser.number("seconds", 2.0, config::Range{0.0, 3600.0, true, false},
                                       "the figures settle within seconds; an hour at most");

  auto rig_or_none = load_rig_or_report(
      config::resolve_config_argument("rigs", parser.value("config", "cambio")), {});
  if (!rig_or_none) return kExitBadInput;
  config::RigConfig rig = *rig_or_none;
  if (!rig.stereo) {
    std::cerr << "cambio sim-bench: rig " << rig.name << " has no stereo pair to measure\n";
    return kExitBadInput;
  }
  if (parser.has("width") != parser.has("height")) {
    throw UsageError("sim-bench: give both --width and --height");
  }
  if (parser.has("width")) {
    const config::Range side = config::Range::closed(16, sim::kMaxCameraSidePx);
    const std::string why = "the sim renders cameras up to " +
                            std::to_string(sim::kMaxCameraSidePx) +
                            " px a side; below 16 px the figures measure overhead only";
    const long long width = parser.integer("width", 0, side, why);
    const long long height = parser.integer("height", 0, side, why);
    // Same field of view at the new size; centred principal point.
    for (auto& camera : rig.cameras) {
      const double scale = static_cast<double>(width) / camera.width_px;
      camera.focal_x_px *= scale;
      camera.focal_y_px = camera.focal_x_px;
      camera.width_px = static_cast<int>(width);
      camera.height_px = static_cast<int>(height);
      camera.principal_x_px = (camera.width_px - 1) / 2.0;
      camera.principal_y_px = (camera.height_px - 1) / 2.0;
    }
  }
  config::SceneConfig physics_scene, camera_scene;
  try {
    physics_scene = config::load_scene(
        config::resolve_config_argument("scenes", parser.value("scene", "table")));
    camera_scene = config::load_scene(
        config::resolve_config_argument("scenes", parser.value("camera-scene", "vergence")));
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }

  // Physics: the full robot, every sim group commanded, contacts with the table's objects;
  // then the same robot in the camera scene, which has no free bodies (the robot-only cost).
  struct PhysicsFigure {
    double steps_per_s = 0.0;
    double mean_contacts = 0.0;
    int nq = 0;
    int nv = 0;
  };
  const hal::HardwareInfo hardware = config::hardware_description(rig);
  hal::ManualClock clock;  // The benchmark steps physics itself; stamps come from the step count.
  auto measure_physics = [&](const config::SceneConfig& scene) -> PhysicsFigure {
    sim::SimBackend backend(rig, scene, hardware, hal::BackendContext{&clock});
    Exerciser exerciser;
    for (const auto& group : rig.groups) {
      if (group.backend != "sim") continue;
      exerciser.groups.push_back(backend.make_joint_group(group.name));
      exerciser.commands.emplace_back(group.joints.size());
    }
    backend.activate();
    auto& physics = backend.physics();
    // Drives walk switch-on disabled -> operation enabled one transition per step: without
    // this the joints would hold still and the figure would measure an idle robot.
    for (auto& group : exerciser.groups) (void)group->request(hal::DriveRequest::kEnable);
    for (int k = 0; k < 3; ++k) (void)physics.step_once(0);
    const double dt = backend.world().timestep_s();
    std::uint64_t steps = 0;
    std::uint64_t contacts = 0;
    const auto start = Clock::now();
    double elapsed = 0.0;
    while (elapsed < seconds / 2) {
      for (int k = 0; k < 100; ++k) {
        // The joint loop writes at the physics rate, as under the executor.
        exerciser.command(static_cast<double>(steps) * dt);
        if (physics.step_once(static_cast<std::int64_t>(steps) * 1'000'000) != hal::Status::kOk) {
          throw std::runtime_error("the physics step faulted in scene " + scene.name);
        }
        contacts += static_cast<std::uint64_t>(backend.world().data()->ncon);
        ++steps;
      }
      elapsed = seconds_since(start);
    }
    return {static_cast<double>(steps) / elapsed,
            static_cast<double>(contacts) / static_cast<double>(steps), backend.world().model()->nq,
            backend.world().model()->nv};
  };
  PhysicsFigure full;
  PhysicsFigure robot_only;
  std::unique_ptr<sim::SimBackend> camera_backend;
  try {
    full = measure_physics(physics_scene);
    robot_only = measure_physics(camera_scene);
    camera_backend =
        std::make_unique<sim::SimBackend>(rig, camera_scene, hardware, hal::BackendContext{&clock});
    // Made now, not at the first camera: the renderer refuses cameras larger than it can draw.
    (void)camera_backend->renderer();
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }
  const double physics_steps_per_s = full.steps_per_s;
  const double mean_contacts = full.mean_contacts;
  const int nq = full.nq;
  const int nv = full.nv;

  // Cameras: the pipeline (HAL grab of both eyes, a physics step between pairs so every pair is
  // a new frame) against the raw MuJoCo loop, alternated in rounds so that both see the same
  // machine load.
  sim::SimBackend& backend = *camera_backend;
  backend.activate();
  auto left = backend.make_camera(rig.stereo->left_camera);
  auto right = backend.make_camera(rig.stereo->right_camera);
  const auto& intrinsics = left->info().intrinsics;
  hal::Image left_image(intrinsics.width_px, intrinsics.height_px, left->info().format);
  hal::Image right_image(intrinsics.width_px, intrinsics.height_px, right->info().format);
  sim::Renderer& renderer = backend.renderer();
  const int left_id = backend.world().camera_id(rig.stereo->left_camera);
  const int right_id = backend.world().camera_id(rig.stereo->right_camera);
  std::vector<std::uint8_t> raw(static_cast<std::size_t>(intrinsics.width_px) *
                                intrinsics.height_px * 3);
  std::int64_t stamp_ns = 0;

  auto pipeline_round = [&](double budget_s) {
    int pairs = 0;
    const auto start = Clock::now();
    double physics_s = 0.0;
    while (seconds_since(start) < budget_s) {
      const auto physics_start = Clock::now();
      stamp_ns += 1'000'000;
      (void)backend.physics().step_once(stamp_ns);
      physics_s += seconds_since(physics_start);
      if (left->grab(left_image) != hal::Status::kOk ||
          right->grab(right_image) != hal::Status::kOk) {
        throw std::runtime_error("a camera grab failed during the benchmark");
      }
      ++pairs;
    }
    return std::pair<int, double>{pairs, seconds_since(start) - physics_s};
  };
  auto raw_round = [&](double budget_s) {
    int pairs = 0;
    const auto start = Clock::now();
    const sim::Renderer::Lease lease(renderer, sim::Renderer::Lease::Mode::kWait);
    while (seconds_since(start) < budget_s) {
      renderer.render_raw_reference(left_id, intrinsics.width_px, intrinsics.height_px, raw.data());
      renderer.render_raw_reference(right_id, intrinsics.width_px, intrinsics.height_px,
                                    raw.data());
      ++pairs;
    }
    return std::pair<int, double>{pairs, seconds_since(start)};
  };
  (void)pipeline_round(0.2);  // Warm-up: JIT-compiled llvmpipe shaders, caches.
  (void)raw_round(0.2);
  // Short alternating rounds; the ratio is the median of the rounds' ratios, so a burst of
  // load from another process skews one round, not the figure.
  constexpr int kRounds = 10;
  int pipeline_pairs = 0, raw_pairs = 0;
  double pipeline_s = 0.0, raw_s = 0.0;
  std::vector<double> ratios;
  for (int round = 0; round < kRounds; ++round) {
    const auto [p, ps] = pipeline_round(seconds / kRounds);
    const auto [r, rs] = raw_round(seconds / kRounds);
    pipeline_pairs += p;
    pipeline_s += ps;
    raw_pairs += r;
    raw_s += rs;
    ratios.push_back((p / ps) / (r / rs));
  }
  std::sort(ratios.begin(), ratios.end());
  const double ratio = 0.5 * (ratios[kRounds / 2 - 1] + ratios[kRounds / 2]);
  const double camera_fps = pipeline_pairs / pipeline_s;
  const double raw_fps = raw_pairs / raw_s;
  const sim::RendererDescription& rendering = renderer.description();
  // What there was to render on: listed for the report, whichever device the renderer took.
  std::optional<std::vector<sim::EglDevice>> devices;
  std::string devices_problem;
  try {
    devices = sim::enumerate_egl_devices();
  } catch (const std::runtime_error& error) {
    devices_problem = error.what();
  }

  if (parser.flag_set("json")) {
    Json figures = {{"physics_steps_per_s", std::llround(physics_steps_per_s)},
                    {"physics_scene", physics_scene.name},
                    {"nq", nq},
                    {"nv", nv},
                    {"mean_contacts", as_printed(mean_contacts, "%.2f")},
                    {"physics_robot_only_steps_per_s", std::llround(robot_only.steps_per_s)},
                    {"width", intrinsics.width_px},
                    {"height", intrinsics.height_px},
                    {"camera_stereo_fps", as_printed(camera_fps, "%.1f")},
                    {"raw_mujoco_stereo_fps", as_printed(raw_fps, "%.1f")},
                    {"camera_vs_raw", as_printed(camera_fps / raw_fps, "%.3f")},
                    {"camera_scene", camera_scene.name},
                    {"format", left->info().format == hal::PixelFormat::kRgb8 ? "rgb8" : "grey8"}};
    add_renderer_fields(figures, rendering);
    figures["egl_devices"] = devices ? egl_devices_json(*devices) : Json(nullptr);
    if (!devices) std::cerr << "cambio sim-bench: " << devices_problem << "\n";
    std::cout << json_text(figures);
  } else {
    std::printf("sim-bench (%s, %s)\n", rendering.gl_renderer.c_str(), rendering.gl_vendor.c_str());
    const std::string fallback = rendering.fallback_reason.empty()
                                     ? ""
                                     : " (auto fell back: " + rendering.fallback_reason + ")";
    std::printf("  rendering on      %s%s\n", rendering.egl_platform.c_str(), fallback.c_str());
    std::printf("  EGL devices       %s\n",
                devices ? sim::describe_egl_devices(*devices).c_str() : devices_problem.c_str());
    std::printf("  physics           %10.0f steps/s  (rig %s, scene %s, nv %d, %.1f contacts)\n",
                physics_steps_per_s, rig.name.c_str(), physics_scene.name.c_str(), nv,
                mean_contacts);
    std::printf("  physics, no props %10.0f steps/s  (scene %s, nv %d)\n", robot_only.steps_per_s,
                camera_scene.name.c_str(), robot_only.nv);
    std::printf("  camera pipeline   %10.1f stereo frames/s at %dx%d\n", camera_fps,
                intrinsics.width_px, intrinsics.height_px);
    std::printf("  raw MuJoCo        %10.1f stereo frames/s (render + read back)\n", raw_fps);
    std::printf("  pipeline / raw    %10.1f %%  (median of %d alternating rounds)\n", 100.0 * ratio,
                kRounds);
  }
  return kExitOk;
}

}  // namespace cambio::app
