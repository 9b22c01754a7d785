#include "sim_bench.hpp"

#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cambio/config/hardware_description.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/sim/egl_devices.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "camera_throughput.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "physics_throughput.hpp"
#include "sim_bench_report.hpp"

namespace cambio::app {

namespace {

/// Same field of view at the new size; centred principal point.
void resize_eyes(config::RigConfig& rig, const EyeSize& size) {
  for (auto& camera : rig.cameras) {
    const double scale = static_cast<double>(size.width_px) / camera.width_px;
    camera.focal_x_px *= scale;
    camera.focal_y_px = camera.focal_x_px;
    camera.width_px = size.width_px;
    camera.height_px = size.height_px;
    camera.principal_x_px = (camera.width_px - 1) / 2.0;
    camera.principal_y_px = (camera.height_px - 1) / 2.0;
  }
}

/// The rig twice: `whole_frame` with no eye foveated, for the whole-frame pipeline, and
/// `measured`, for the physics and the foveated pipeline, keeping the rig's foveation when an
/// eye's fits its image (`foveation`, reported) and with none otherwise.
struct FoveationSplit {
  config::RigConfig whole_frame;
  config::RigConfig measured;
  std::optional<config::SimFoveationConfig> foveation;
};

FoveationSplit split_foveation(const config::RigConfig& rig) {
  FoveationSplit split{rig, rig, std::nullopt};
  for (auto& camera : split.whole_frame.cameras) {
    if (camera.sim_foveation.enabled() &&
        !camera.sim_foveation.fits(camera.width_px, camera.height_px)) {
      std::cerr << "sim-bench: the rig's foveation (fovea " << camera.sim_foveation.fovea_px
                << " px, periphery 1/" << camera.sim_foveation.periphery_downscale
                << ") does not fit " << camera.width_px << "x" << camera.height_px
                << ": whole frames only\n";
    } else if (camera.sim_foveation.enabled()) {
      split.foveation = camera.sim_foveation;
    }
    camera.sim_foveation = {};
  }
  if (!split.foveation) {
    for (auto& camera : split.measured.cameras) camera.sim_foveation = {};
  }
  return split;
}

/// The camera scene's backends, whole-frame and (when foveated) foveated. Their renderers are
/// made now, not at the first camera: the renderer refuses cameras larger than it can draw.
struct CameraBackends {
  std::unique_ptr<sim::SimBackend> whole;
  std::unique_ptr<sim::SimBackend> foveated;
};

CameraBackends make_camera_backends(const FoveationSplit& split, const config::SceneConfig& scene,
                                    const hal::HardwareInfo& hardware, hal::Clock& clock) {
  CameraBackends backends;
  backends.whole = std::make_unique<sim::SimBackend>(split.whole_frame, scene, hardware,
                                                     hal::BackendContext{&clock});
  (void)backends.whole->renderer();
  if (split.foveation) {
    backends.foveated = std::make_unique<sim::SimBackend>(split.measured, scene, hardware,
                                                          hal::BackendContext{&clock});
    (void)backends.foveated->renderer();
  }
  return backends;
}

/// What there was to render on: listed for the report, whichever device the renderer took.
void list_egl_devices(SimBenchFigures& figures) {
  try {
    figures.devices = sim::enumerate_egl_devices();
  } catch (const std::runtime_error& error) {
    figures.devices_problem = error.what();
  }
}

}  // namespace

int run_sim_bench(SimBenchOptions options) {
  if (options.eye_size) resize_eyes(options.rig, *options.eye_size);
  const hal::HardwareInfo hardware = config::hardware_description(options.rig);
  hal::ManualClock clock;  // The benchmark steps physics itself; stamps come from the step count.
  const FoveationSplit split = split_foveation(options.rig);
  SimBenchFigures figures;
  figures.rig_name = options.rig.name;
  figures.physics_scene = options.physics_scene.name;
  figures.camera_scene = options.camera_scene.name;
  figures.foveation = split.foveation;
  // Physics: the full robot, every sim group commanded, contacts with the table's objects;
  // then the same robot in the camera scene, which has no free bodies (the robot-only cost).
  // Each takes half the measurement time.
  CameraBackends backends;
  try {
    figures.physics = measure_physics(split.measured, options.physics_scene, hardware, clock,
                                      options.seconds / 2);
    figures.robot_only =
        measure_physics(split.measured, options.camera_scene, hardware, clock, options.seconds / 2);
    backends = make_camera_backends(split, options.camera_scene, hardware, clock);
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }
  // Cameras: the pipeline on whole frames and, if the rig's eyes are foveated, foveated, against
  // the raw MuJoCo loop on whole frames.
  figures.cameras =
      measure_cameras(*backends.whole, backends.foveated.get(), split.measured, options.seconds);
  figures.rendering = backends.whole->renderer().description();
  list_egl_devices(figures);
  if (options.json) {
    print_sim_bench_json(figures);
  } else {
    print_sim_bench_table(figures);
  }
  return kExitOk;
}

}  // namespace cambio::app
