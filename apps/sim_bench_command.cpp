// `cambio sim-bench [--json] [--width W --height H]`: in one run, the sim's physics steps per
// second for the full robot, the stereo frames per second of its camera pipeline (render, read
// back, flip, convert, noise: what Camera::grab does), and, as the reference, a raw MuJoCo
// render-and-read loop of the same scene at the same resolution on the same GL context.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
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

// Stereo pairs rendered in some seconds of wall time.
struct Round {
  int pairs = 0;
  double seconds = 0.0;
  double fps() const { return seconds > 0.0 ? pairs / seconds : 0.0; }
  Round& operator+=(const Round& other) {
    pairs += other.pairs;
    seconds += other.seconds;
    return *this;
  }
};

double median_of(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// Both eyes of a sim backend grabbed through the HAL, a physics step between pairs so that every
// pair is a new frame; the physics step's time is not counted.
class StereoPipeline {
 public:
  StereoPipeline(sim::SimBackend& backend, const config::RigConfig& rig) : backend_(backend) {
    backend_.activate();
    left_ = backend_.make_camera(rig.stereo->left_camera);
    right_ = backend_.make_camera(rig.stereo->right_camera);
    const auto& k = left_->info().intrinsics;
    left_image_ = hal::Image(k.width_px, k.height_px, left_->info().format);
    right_image_ = hal::Image(k.width_px, k.height_px, right_->info().format);
  }
  const hal::CameraIntrinsics& intrinsics() const { return left_->info().intrinsics; }
  hal::PixelFormat format() const { return left_->info().format; }

  Round round(double budget_s) {
    int pairs = 0;
    const auto start = Clock::now();
    double physics_s = 0.0;
    while (seconds_since(start) < budget_s) {
      const auto physics_start = Clock::now();
      stamp_ns_ += 1'000'000;
      (void)backend_.physics().step_once(stamp_ns_);
      physics_s += seconds_since(physics_start);
      if (left_->grab(left_image_) != hal::Status::kOk ||
          right_->grab(right_image_) != hal::Status::kOk) {
        throw std::runtime_error("a camera grab failed during the benchmark");
      }
      ++pairs;
    }
    return {pairs, seconds_since(start) - physics_s};
  }

 private:
  sim::SimBackend& backend_;
  std::unique_ptr<hal::Camera> left_;
  std::unique_ptr<hal::Camera> right_;
  hal::Image left_image_;
  hal::Image right_image_;
  std::int64_t stamp_ns_ = 0;
};

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
      if (group.backend != sim::SimBackend::kName) continue;
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
  // The rig's foveation, if its eyes have one; the whole-frame pipeline is measured without it.
  std::optional<config::SimFoveationConfig> foveation;
  config::RigConfig whole_frame_rig = rig;
  for (auto& camera : whole_frame_rig.cameras) {
    if (camera.sim_foveation.enabled() &&
        !camera.sim_foveation.fits(camera.width_px, camera.height_px)) {
      std::cerr << "sim-bench: the rig's foveation (fovea " << camera.sim_foveation.fovea_px
                << " px, periphery 1/" << camera.sim_foveation.periphery_downscale
                << ") does not fit " << camera.width_px << "x" << camera.height_px
                << ": whole frames only\n";
    } else if (camera.sim_foveation.enabled()) {
      foveation = camera.sim_foveation;
    }
    camera.sim_foveation = {};
  }
  if (!foveation) {
    for (auto& camera : rig.cameras) camera.sim_foveation = {};
  }
  PhysicsFigure full;
  PhysicsFigure robot_only;
  std::unique_ptr<sim::SimBackend> whole_backend;
  std::unique_ptr<sim::SimBackend> foveated_backend;
  try {
    full = measure_physics(physics_scene);
    robot_only = measure_physics(camera_scene);
    whole_backend = std::make_unique<sim::SimBackend>(whole_frame_rig, camera_scene, hardware,
                                                      hal::BackendContext{&clock});
    // Made now, not at the first camera: the renderer refuses cameras larger than it can draw.
    (void)whole_backend->renderer();
    if (foveation) {
      foveated_backend = std::make_unique<sim::SimBackend>(rig, camera_scene, hardware,
                                                           hal::BackendContext{&clock});
      (void)foveated_backend->renderer();
    }
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }
  const double physics_steps_per_s = full.steps_per_s;
  const double mean_contacts = full.mean_contacts;
  const int nq = full.nq;
  const int nv = full.nv;

  // Cameras: the pipeline (HAL grab of both eyes, a physics step between pairs so every pair is
  // a new frame) on whole frames and, if the rig's eyes are foveated, foveated, against the raw
  // MuJoCo loop on whole frames, alternated in rounds so that all see the same machine load.
  StereoPipeline whole(*whole_backend, rig);
  std::optional<StereoPipeline> foveated;
  if (foveated_backend) foveated.emplace(*foveated_backend, rig);
  const auto& intrinsics = whole.intrinsics();
  sim::Renderer& renderer = whole_backend->renderer();
  const int left_id = whole_backend->world().camera_id(rig.stereo->left_camera);
  const int right_id = whole_backend->world().camera_id(rig.stereo->right_camera);
  std::vector<std::uint8_t> raw(static_cast<std::size_t>(intrinsics.width_px) *
                                intrinsics.height_px * 3);
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
    return Round{pairs, seconds_since(start)};
  };
  (void)whole.round(0.2);  // Warm-up: JIT-compiled llvmpipe shaders, caches.
  if (foveated) (void)foveated->round(0.2);
  (void)raw_round(0.2);
  // Short alternating rounds; each ratio is the median of the rounds' ratios, so a burst of
  // load from another process skews one round, not the figure.
  constexpr int kRounds = 10;
  Round whole_total, foveated_total, raw_total;
  std::vector<double> whole_ratios, foveated_ratios;
  for (int round = 0; round < kRounds; ++round) {
    const Round w = whole.round(seconds / kRounds);
    const Round f = foveated ? foveated->round(seconds / kRounds) : Round{};
    const Round r = raw_round(seconds / kRounds);
    whole_total += w;
    foveated_total += f;
    raw_total += r;
    whole_ratios.push_back(w.fps() / r.fps());
    if (foveated) foveated_ratios.push_back(f.fps() / r.fps());
  }
  const double camera_fps = whole_total.fps();
  const double raw_fps = raw_total.fps();
  const double ratio = median_of(whole_ratios);
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
    Json figures = {
        {"physics_steps_per_s", std::llround(physics_steps_per_s)},
        {"physics_scene", physics_scene.name},
        {"nq", nq},
        {"nv", nv},
        {"mean_contacts", as_printed(mean_contacts, "%.2f")},
        {"physics_robot_only_steps_per_s", std::llround(robot_only.steps_per_s)},
        {"width", intrinsics.width_px},
        {"height", intrinsics.height_px},
        {"camera_stereo_fps", as_printed(camera_fps, "%.1f")},
        {"raw_mujoco_stereo_fps", as_printed(raw_fps, "%.1f")},
        {"camera_vs_raw", as_printed(ratio, "%.3f")},
        {"foveation", foveation ? Json{{"periphery_downscale", foveation->periphery_downscale},
                                       {"fovea_px", foveation->fovea_px}}
                                : Json(nullptr)},
        {"foveated_stereo_fps",
         foveated ? Json(as_printed(foveated_total.fps(), "%.1f")) : Json(nullptr)},
        {"foveated_vs_raw",
         foveated ? Json(as_printed(median_of(foveated_ratios), "%.3f")) : Json(nullptr)},
        {"camera_scene", camera_scene.name},
        {"format", whole.format() == hal::PixelFormat::kRgb8 ? "rgb8" : "grey8"}};
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
    if (foveated) {
      std::printf(
          "  foveated pipeline %10.1f stereo frames/s (periphery 1/%d, fovea %d px), "
          "%.2fx raw\n",
          foveated_total.fps(), foveation->periphery_downscale, foveation->fovea_px,
          median_of(foveated_ratios));
    }
  }
  return kExitOk;
}

}  // namespace cambio::app
