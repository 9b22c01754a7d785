#include "fuzz_targets.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/config/experiment_config.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/perception/perception_config.hpp"
#include "cambio/perception/sensory_servo.hpp"

namespace cambio::fuzz {

namespace {

std::string text_of(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Aborts (a libFuzzer crash) when a loaded config breaks a bound its loader promises.
void require(bool holds, const char* bound) {
  if (holds) return;
  std::fprintf(stderr, "fuzz: a config that loaded breaks the bound: %s\n", bound);
  std::abort();
}

/// The bounds rig_loader.hpp promises for a loaded rig, and hal's description of it (which
/// throws on what the loader should have refused).
void check_rig(const config::RigConfig& rig) {
  require(!rig.joints.empty() && rig.joints.size() <= config::kMaxJoints, "kMaxJoints");
  std::int64_t pixels = 0;
  for (const auto& camera : rig.cameras) {
    require(camera.width_px >= 1 && camera.width_px <= config::kMaxCameraSide_px &&
                camera.height_px >= 1 && camera.height_px <= config::kMaxCameraSide_px,
            "kMaxCameraSide_px");
    pixels += std::int64_t{camera.width_px} * camera.height_px;
  }
  require(pixels <= config::kMaxCameraPixels, "kMaxCameraPixels");
  require(rig.sim.physics_rate_hz >= config::kMinPhysicsRate_hz &&
              rig.sim.physics_rate_hz <= config::kMaxRate_hz,
          "physics rate");
  for (const auto& joint : rig.joints) {
    require(joint.servo.dead_time_s >= 0.0 && joint.servo.dead_time_s <= config::kMaxDeadTime_s,
            "kMaxDeadTime_s");
  }
  for (const auto& sensor : rig.touch_sensors) {
    require(sensor.fingertip_x_m >= 0.01 && sensor.fingertip_x_m <= 1.0 &&
                sensor.fingertip_y_m >= 0.0 && sensor.fingertip_y_m <= 0.2,
            "fingertip_xy_m");
  }
  for (const auto& loop : rig.loops) {
    require(loop.rate_hz >= config::kMinRate_hz && loop.rate_hz <= config::kMaxRate_hz,
            "loop rate");
    require(loop.cpu >= -1 && loop.cpu <= config::kMaxCpu, "kMaxCpu");
  }
  const hal::HardwareInfo hardware = config::hardware_description(rig);
  require(hardware.joints.size() == rig.joints.size(), "every joint described");
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

int rig(const std::uint8_t* data, std::size_t size) {
  try {
    check_rig(config::load_rig_from_string(text_of(data, size), "fuzz_rig.yaml"));
  } catch (const config::ConfigError&) {
  }
  return 0;
}

int scene(const std::uint8_t* data, std::size_t size) {
  try {
    const config::SceneConfig scene =
        config::load_scene_from_string(text_of(data, size), "fuzz_scene.yaml");
    require(scene.objects.size() <= config::kMaxSceneObjects, "kMaxSceneObjects");
  } catch (const config::ConfigError&) {
  }
  return 0;
}

int experiment(const std::uint8_t* data, std::size_t size) {
  static const std::string name = config::shipped_config_dir() + "/experiments/fuzz_input.yaml";
  try {
    const config::ExperimentConfig experiment =
        config::load_experiment_from_string(text_of(data, size), name);
    require(
        experiment.duration_s > 0.0 && experiment.duration_s <= config::kMaxExperimentDuration_s,
        "kMaxExperimentDuration_s");
    check_rig(experiment.rig);
  } catch (const config::ConfigError&) {
  }
  return 0;
}

int perception(const std::uint8_t* data, std::size_t size) {
  perception::SsmConfig ssm;
  try {
    config::ConfigDocument document =
        config::ConfigDocument::from_string(text_of(data, size), "fuzz_perception.yaml");
    config::MapReader root = document.root();
    ssm = perception::read_ssm_config(root);
    document.issues()->throw_if_any();
  } catch (const config::ConfigError&) {
    return 0;
  }
  // What the loader accepted, the SSM must build; its buffers are what the config sizes.
  const perception::SensoryServo servo(ssm, config::kMaxCameraSide_px, config::kMaxCameraSide_px);
  const perception::SsmFrame frame = servo.make_frame();
  require(frame.maps[0].levels() == ssm.retina.levels, "a frame of every level");
  return 0;
}

int set_override(const std::uint8_t* data, std::size_t size) {
  static const std::string rig_text = read_file(config::find_shipped_config("rigs/cambio.yaml"));
  std::vector<config::ConfigOverride> overrides;
  try {
    std::istringstream arguments(text_of(data, size));
    for (std::string argument; std::getline(arguments, argument, '\0');) {
      overrides.push_back(config::parse_override(argument));
    }
    check_rig(config::load_rig_from_string(rig_text, "cambio.yaml", overrides));
  } catch (const config::ConfigError&) {
  }
  return 0;
}

}  // namespace cambio::fuzz
