#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/hal/clock.hpp"
#include "cambio/hal/image.hpp"
#include "cambio/sim/sim_backend.hpp"

namespace cambio::sim::testing {

inline config::RigConfig load_shipped_rig(const std::string& name = "cambio") {
  return config::load_rig(config::find_shipped_config("rigs/" + name + ".yaml"));
}

inline config::SceneConfig load_shipped_scene(const std::string& name) {
  return config::load_scene(config::find_shipped_config("scenes/" + name + ".yaml"));
}

/// Shrinks every camera to 160x120 with the same 60 deg horizontal field of view (focal from
/// 80 / tan(30 deg)), keeping the principal point centred: small frames keep tests quick, and
/// the geometry tests cover the full size. Whole frames: the shipped foveation's 160 px fovea
/// does not fit.
inline void use_small_cameras(config::RigConfig& rig) {
  for (auto& camera : rig.cameras) {
    camera.sim_foveation = {};
    camera.width_px = 160;
    camera.height_px = 120;
    camera.focal_x_px = camera.focal_y_px = 138.564;
    camera.principal_x_px = 79.5;
    camera.principal_y_px = 59.5;
  }
}

/// A sim backend built directly, as the "sim" maker builds it: the hardware description from the
/// rig, the run's clock from the caller (a ManualClock, or an executor's clock()).
inline std::unique_ptr<SimBackend> make_sim(const config::RigConfig& rig,
                                            const config::SceneConfig& scene, hal::Clock& clock,
                                            std::uint64_t seed = 0, bool realtime = false,
                                            const MjcfOptions& mjcf_options = {}) {
  return std::make_unique<SimBackend>(rig, scene, config::hardware_description(rig),
                                      hal::BackendContext{&clock, seed, realtime}, mjcf_options);
}

/// A scene with nothing in it (quick to build; no floor to collide with).
inline config::SceneConfig empty_scene() {
  return config::load_scene_from_string("world: {floor: false}\n", "empty.yaml");
}

/// Puts a rig group on another backend (the sim then only builds its joints, and may follow it).
inline void set_group_backend(config::RigConfig& rig, const std::string& group,
                              const std::string& backend) {
  for (auto& g : rig.groups) {
    if (g.name == group) g.backend = backend;
  }
}

inline void set_initial(config::RigConfig& rig, const std::string& joint, double position_rad) {
  for (auto& j : rig.joints) {
    if (j.name == joint) j.initial_position_rad = position_rad;
  }
}

/// Turns every noise source off so geometric tests are exact, and the eyes' foveation: whole
/// frames at full resolution (tests of foveation set it again).
inline void make_ideal(config::RigConfig& rig) {
  for (auto& joint : rig.joints) {
    joint.servo.motion_noise_std_rad = 0.0;
    joint.servo.encoder_counts_per_rev = 0;
    joint.servo.backlash_rad = 0.0;
  }
  for (auto& camera : rig.cameras) {
    camera.image_noise_std = 0.0;
    camera.sim_foveation = {};
  }
}

struct Centroid {
  double x = 0.0;
  double y = 0.0;
  double weight = 0.0;
};

/// Centroid of the pixels where red dominates (a red marker on a grey or blue world). A plain
/// mask, not weighted by intensity: the marker is lit from above, so weighting by brightness
/// would pull the centroid up. Without MSAA the mask's edge is exact to the pixel grid.
inline Centroid red_centroid(const hal::Image& image) {
  Centroid c;
  for (int y = 0; y < image.height_px; ++y) {
    const std::uint8_t* row = image.row(y);
    for (int x = 0; x < image.width_px; ++x) {
      const double r = row[3 * x], g = row[3 * x + 1], b = row[3 * x + 2];
      if (r < 30.0 || r < 2.0 * std::max(g, b)) continue;
      c.x += x;
      c.y += y;
      c.weight += 1.0;
    }
  }
  if (c.weight > 0.0) {
    c.x /= c.weight;
    c.y /= c.weight;
  }
  return c;
}

}  // namespace cambio::sim::testing
