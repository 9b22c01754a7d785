#include "sim_bench_report.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>

#include "json_output.hpp"
#include "renderer_report.hpp"

namespace cambio::app {

namespace {

Json foveation_json(const SimBenchFigures& figures) {
  if (!figures.foveation) return Json(nullptr);
  return Json{{"periphery_downscale", figures.foveation->periphery_downscale},
              {"fovea_px", figures.foveation->fovea_px}};
}

}  // namespace

void print_sim_bench_json(const SimBenchFigures& figures) {
  const CameraFigures& c = figures.cameras;
  Json json = {{"physics_steps_per_s", std::llround(figures.physics.steps_per_s)},
               {"physics_scene", figures.physics_scene},
               {"nq", figures.physics.nq},
               {"nv", figures.physics.nv},
               {"mean_contacts", as_printed(figures.physics.mean_contacts, "%.2f")},
               {"physics_robot_only_steps_per_s", std::llround(figures.robot_only.steps_per_s)},
               {"width", c.width_px},
               {"height", c.height_px},
               {"camera_stereo_fps", as_printed(c.camera_fps, "%.1f")},
               {"raw_mujoco_stereo_fps", as_printed(c.raw_fps, "%.1f")},
               {"camera_vs_raw", as_printed(c.camera_vs_raw, "%.3f")},
               {"foveation", foveation_json(figures)},
               {"foveated_stereo_fps",
                c.foveated_fps ? Json(as_printed(*c.foveated_fps, "%.1f")) : Json(nullptr)},
               {"foveated_vs_raw",
                c.foveated_vs_raw ? Json(as_printed(*c.foveated_vs_raw, "%.3f")) : Json(nullptr)},
               {"camera_scene", figures.camera_scene},
               {"format", c.format == hal::PixelFormat::kRgb8 ? "rgb8" : "grey8"}};
  add_renderer_fields(json, figures.rendering);
  json["egl_devices"] = figures.devices ? egl_devices_json(*figures.devices) : Json(nullptr);
  if (!figures.devices) std::cerr << "cambio sim-bench: " << figures.devices_problem << "\n";
  std::cout << json_text(json);
}

void print_sim_bench_table(const SimBenchFigures& figures) {
  const sim::RendererDescription& rendering = figures.rendering;
  const CameraFigures& c = figures.cameras;
  std::printf("sim-bench (%s, %s)\n", rendering.gl_renderer.c_str(), rendering.gl_vendor.c_str());
  const std::string fallback = rendering.fallback_reason.empty()
                                   ? ""
                                   : " (auto fell back: " + rendering.fallback_reason + ")";
  std::printf("  rendering on      %s%s\n", rendering.egl_platform.c_str(), fallback.c_str());
  std::printf("  EGL devices       %s\n", figures.devices
                                              ? sim::describe_egl_devices(*figures.devices).c_str()
                                              : figures.devices_problem.c_str());
  std::printf("  physics           %10.0f steps/s  (rig %s, scene %s, nv %d, %.1f contacts)\n",
              figures.physics.steps_per_s, figures.rig_name.c_str(), figures.physics_scene.c_str(),
              figures.physics.nv, figures.physics.mean_contacts);
  std::printf("  physics, no props %10.0f steps/s  (scene %s, nv %d)\n",
              figures.robot_only.steps_per_s, figures.camera_scene.c_str(), figures.robot_only.nv);
  std::printf("  camera pipeline   %10.1f stereo frames/s at %dx%d\n", c.camera_fps, c.width_px,
              c.height_px);
  std::printf("  raw MuJoCo        %10.1f stereo frames/s (render + read back)\n", c.raw_fps);
  std::printf("  pipeline / raw    %10.1f %%  (median of %d alternating rounds)\n",
              100.0 * c.camera_vs_raw, c.rounds);
  if (c.foveated_fps) {
    std::printf(
        "  foveated pipeline %10.1f stereo frames/s (periphery 1/%d, fovea %d px), "
        "%.2fx raw\n",
        *c.foveated_fps, figures.foveation->periphery_downscale, figures.foveation->fovea_px,
        *c.foveated_vs_raw);
  }
}

}  // namespace cambio::app
