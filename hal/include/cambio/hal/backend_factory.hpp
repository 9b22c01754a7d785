#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/hal/backend_offers.hpp"
#include "cambio/hal/camera.hpp"
#include "cambio/hal/clock.hpp"
#include "cambio/hal/closest_name.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/hal/joint_group.hpp"
#include "cambio/hal/joint_state_tap.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/touch_sensor.hpp"

namespace cambio::hal {

/// What every backend of a run is given besides the hardware description.
struct BackendContext {
  /// The run's one clock, owned by the executor (CLOCK_MONOTONIC under the realtime executor,
  /// simulated time under lockstep). Every backend stamps with it, so a rig mixing sim cameras
  /// with CAN joints has one time base.
  Clock* clock = nullptr;
  std::uint64_t seed = 0;  ///< Seeds every noise source (sim).
  bool realtime = false;   ///< Paced to the wall clock (realtime executor) or lockstep.
};

/// A loop a backend needs run, with the rate it must run at (e.g. the sim's physics step at
/// the rig's sim.physics_rate_hz).
struct BackendLoop {
  Loop* loop = nullptr;  ///< Owned by the backend.
  double rate_hz = 0.0;
  int priority = 0;  ///< SCHED_FIFO priority under the realtime executor; 0 = normal.
};

/// Thrown when a rig names a backend this build cannot make, or asks a backend for something it
/// cannot do.
class BackendUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One backend instance serves every device of the rig that names it (the sim's world is shared
/// by its joint groups and cameras; a CAN backend shares its buses). Lifecycle, called by the
/// application from one thread, outside the loops:
///   make_*() / follow_group()  devices, while building the run (may allocate and throw)
///   configure()                after every device exists: write drive parameters, open buses
///                              (may throw std::runtime_error with a clear message)
///   activate()                 start buses and streams; drives are enabled by the joint loop's
///                              requests, at their measured positions
///   deactivate()               quick stop and disable every drive, stop the streams; also runs
///                              when a signal stops the run. noexcept, idempotent.
class Backend {
 public:
  virtual ~Backend() = default;

  virtual std::unique_ptr<JointGroup> make_joint_group(std::string_view group_name) = 0;
  virtual std::unique_ptr<Camera> make_camera(std::string_view camera_name) = 0;
  virtual std::unique_ptr<TouchSensor> make_touch_sensor(std::string_view sensor_name) = 0;

  /// A group of the rig that another backend drives: this backend's model of those joints
  /// follows the positions `leader` reports (the sim's head follows CAN drives, so its cameras
  /// see what the drives did). `leader` outlives the backend's loops. Throws BackendUnavailable
  /// if this backend cannot follow.
  virtual void follow_group(const JointGroupInfo& group, const JointStateSource& leader) {
    (void)leader;
    throw BackendUnavailable("this backend cannot follow joint group '" + group.name +
                             "' driven by backend '" + group.backend + "'");
  }

  /// True for a backend that models the whole robot (the simulator): the run has it follow
  /// every joint group another backend drives, so its cameras and touch sensors see what those
  /// drives did.
  virtual bool follows_other_backends() const { return false; }

  virtual void configure() {}
  virtual void activate() {}
  virtual void deactivate() noexcept {}

  /// Adds what the backend offers besides its devices (ground truth, counters, a renderer) to
  /// `offers`, as references it keeps owning. Called once, after configure().
  virtual void offer(BackendOffers& offers) { (void)offers; }

  /// Loops the backend needs run (the sim's physics step), with their rates. The executor runs
  /// them with the application's loops; the backend keeps ownership.
  virtual std::vector<BackendLoop> loops() = 0;
};

/// What the run must know of a backend before it makes one.
struct BackendTraits {
  /// It drives real devices, so the run is paced by the wall clock (the realtime executor, whose
  /// clock every backend is then given).
  bool paced_by_wall_clock = false;
};

/// A setting of the rig a backend cannot work with, found before anything is built: where, as the
/// rig file's key path (e.g. "can_buses.can0.bitrate_bit_s"; the application turns it into a
/// file:line:column), and what was expected and found.
struct SettingProblem {
  std::string key_path;
  std::string message;
};

/// Builds backends by the name the rig file gives (`backend: sim`, `backend: socketcan`).
/// Each backend library registers its maker; a name that is declared but not built, or unknown,
/// is refused with a message that says which names are available.
class BackendFactory {
 public:
  using Maker = std::function<std::unique_ptr<Backend>(const HardwareInfo&, const BackendContext&)>;
  /// A backend's own check of the settings it reads (its section of the rig file, as given to its
  /// maker), over the whole rig: what it needs and is missing, what cannot work together.
  using Checker = std::function<std::vector<SettingProblem>(const HardwareInfo&)>;

  void register_backend(std::string name, Maker maker, BackendTraits traits = {},
                        Checker checker = {}) {
    unbuilt_.erase(name);
    traits_[name] = traits;
    if (checker) {
      checkers_[name] = std::move(checker);
    } else {
      checkers_.erase(name);
    }
    makers_[std::move(name)] = std::move(maker);
  }

  /// Every registered backend's check of `hardware`, in name order: the step `check-config` and
  /// a run take before anything starts. A backend checks its settings wherever they appear (the
  /// CANopen backend checks every group that names a bus, whichever backend drives it).
  std::vector<SettingProblem> check(const HardwareInfo& hardware) const {
    std::vector<SettingProblem> problems;
    for (const auto& [name, checker] : checkers_) {
      for (auto& problem : checker(hardware)) problems.push_back(std::move(problem));
    }
    return problems;
  }

  /// The traits `name` was registered with; the defaults for a name not registered (make()
  /// refuses it).
  BackendTraits traits(std::string_view name) const {
    const auto it = traits_.find(name);
    return it != traits_.end() ? it->second : BackendTraits{};
  }

  /// A backend the rig format knows but this build does not carry, and why (refused by make()
  /// with that reason).
  void declare_unbuilt(std::string name, std::string reason) {
    if (!has(name)) unbuilt_[std::move(name)] = std::move(reason);
  }

  bool has(std::string_view name) const { return makers_.find(name) != makers_.end(); }

  std::vector<std::string> available() const {
    std::vector<std::string> names;
    for (const auto& [name, maker] : makers_) names.push_back(name);
    return names;
  }

  /// Why `name` cannot be made, e.g. "is not a known backend (available: sim, socketcan)";
  /// empty when it can.
  std::string unavailable_reason(std::string_view name) const {
    if (has(name)) return {};
    std::string known;
    for (const auto& available_name : available()) {
      known += known.empty() ? available_name : ", " + available_name;
    }
    const auto unbuilt = unbuilt_.find(name);
    std::string why = unbuilt != unbuilt_.end()
                          ? "is not built in this version of Câmbio (" + unbuilt->second + ")"
                          : "is not a known backend";
    if (const auto nearest = closest_name(name, available());
        nearest && unbuilt == unbuilt_.end()) {
      why += "; did you mean '" + *nearest + "'?";
    }
    return why + " (available: " + (known.empty() ? "none" : known) + ")";
  }

  /// Throws BackendUnavailable naming `requested_by` (e.g. "joint group 'head'").
  std::unique_ptr<Backend> make(std::string_view name, const HardwareInfo& hardware,
                                const BackendContext& context,
                                std::string_view requested_by) const {
    const auto it = makers_.find(name);
    if (it == makers_.end()) {
      throw BackendUnavailable("backend '" + std::string(name) + "' requested by " +
                               std::string(requested_by) + " " + unavailable_reason(name));
    }
    if (context.clock == nullptr) {
      throw std::invalid_argument("backend '" + std::string(name) + "': no clock given");
    }
    return it->second(hardware, context);
  }

 private:
  std::map<std::string, Maker, std::less<>> makers_;
  std::map<std::string, BackendTraits, std::less<>> traits_;
  std::map<std::string, Checker, std::less<>> checkers_;
  std::map<std::string, std::string, std::less<>> unbuilt_;
};

}  // namespace cambio::hal
