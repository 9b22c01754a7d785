#pragma once

// sim-bench's physics figure: how many steps per second the sim's physics makes for the whole
// robot, every sim joint group moving.

#include "cambio/config/rig_config.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/hal/clock.hpp"
#include "cambio/hal/hardware_info.hpp"

namespace cambio::app {

struct PhysicsFigure {
  double steps_per_s = 0.0;
  double mean_contacts = 0.0;  ///< Contacts per step, averaged over the steps measured.
  int nq = 0;                  ///< The model's position coordinates.
  int nv = 0;                  ///< The model's degrees of freedom.
};

/// Builds a sim backend of `rig` in `scene` and steps its physics for `budget_s` of wall time,
/// every sim group commanded along slow sines inside its joints' limits (as the joint loop
/// writes, once per step). `clock` stamps the backend; the steps stamp themselves. Throws
/// config::ConfigError for a rig or scene the sim cannot build, std::runtime_error when a step
/// faults.
PhysicsFigure measure_physics(const config::RigConfig& rig, const config::SceneConfig& scene,
                              const hal::HardwareInfo& hardware, hal::Clock& clock,
                              double budget_s);

}  // namespace cambio::app
