#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/hal/camera.hpp"
#include "cambio/hal/clock.hpp"
#include "cambio/hal/joint_group.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/touch_sensor.hpp"

namespace cambio::config {
struct RigConfig;  // Defined in firmware_config; the HAL only passes it through.
}

namespace cambio::hal {

/// Options that are not part of the rig (they come from the experiment or the command line).
struct BackendOptions {
  std::string scene_path;  ///< Sim: the scene YAML to load around the robot.
  std::uint64_t seed = 0;  ///< Sim: seeds every noise source.
  bool realtime = false;   ///< Paced to the wall clock (realtime executor) or lockstep.
};

/// A loop a backend needs run, with the rate it must run at (e.g. the sim's physics step at
/// the rig's sim.physics_rate_hz).
struct BackendLoop {
  Loop* loop = nullptr;  ///< Owned by the backend.
  double rate_hz = 0.0;
  int priority = 0;  ///< SCHED_FIFO priority under the realtime executor; 0 = normal.
};

/// One backend instance serves every device of the rig that names it (the sim's world is shared
/// by its joint groups and cameras; a CAN backend shares its buses). Built at configure time;
/// its make_* functions may allocate and throw std::runtime_error with a clear message.
class Backend {
 public:
  virtual ~Backend() = default;
  virtual std::unique_ptr<JointGroup> make_joint_group(std::string_view group_name) = 0;
  virtual std::unique_ptr<Camera> make_camera(std::string_view camera_name) = 0;
  virtual std::unique_ptr<TouchSensor> make_touch_sensor(std::string_view sensor_name) = 0;
  /// The clock every loop must use with this backend (sim time, or CLOCK_MONOTONIC).
  virtual Clock& clock() = 0;
  /// Loops the backend needs run (the sim's physics step, a CAN SYNC producer), with their
  /// rates. The executor runs them with the application's loops; the backend keeps ownership.
  virtual std::vector<BackendLoop> loops() = 0;
};

/// Thrown when a rig names a backend this build cannot make.
class BackendUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Builds backends by the name the rig file gives (`backend: sim`, `backend: socketcan`).
/// Each backend library registers its maker; a name that is known but not built in, or unknown,
/// is refused with a message that says which names are available.
class BackendFactory {
 public:
  using Maker =
      std::function<std::unique_ptr<Backend>(const config::RigConfig&, const BackendOptions&)>;

  void register_backend(std::string name, Maker maker) {
    makers_[std::move(name)] = std::move(maker);
  }

  bool has(std::string_view name) const { return makers_.find(std::string(name)) != makers_.end(); }

  std::vector<std::string> available() const {
    std::vector<std::string> names;
    for (const auto& [name, maker] : makers_) names.push_back(name);
    return names;
  }

  /// Throws BackendUnavailable naming `requested_by` (e.g. "joint group 'head'").
  std::unique_ptr<Backend> make(std::string_view name, const config::RigConfig& rig,
                                const BackendOptions& options,
                                std::string_view requested_by) const {
    const auto it = makers_.find(std::string(name));
    if (it == makers_.end()) {
      std::string known;
      for (const auto& available_name : available()) {
        known += known.empty() ? available_name : ", " + available_name;
      }
      std::string why = is_planned(name) ? "is not built yet in this version of Câmbio"
                                         : "is not a known backend";
      throw BackendUnavailable("backend '" + std::string(name) + "' requested by " +
                               std::string(requested_by) + " " + why +
                               " (available: " + (known.empty() ? "none" : known) + ")");
    }
    return it->second(rig, options);
  }

  /// Backends the rig format accepts, built in or not.
  static bool is_planned(std::string_view name) { return name == "sim" || name == "socketcan"; }

 private:
  std::map<std::string, Maker, std::less<>> makers_;
};

}  // namespace cambio::hal
