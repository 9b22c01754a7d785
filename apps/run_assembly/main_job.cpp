#include "main_job.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cambio/config/hardware_description.hpp"
#include "cambio/ros2/perception_link.hpp"
#include "cambio/ros2/ros2_bridge.hpp"
#include "cambio/runtime/lockstep_executor.hpp"
#include "cambio/runtime/realtime_executor.hpp"
#include "controller_params.hpp"
#include "rig_backend_check.hpp"

// MainJob's construction and its runs. The building steps live in main_job_devices.cpp (backends
// and devices), main_job_loops.cpp and main_job_control.cpp (the loops), main_job_trace.cpp,
// main_job_behaviour.cpp, and the report in main_job_report.cpp.

namespace cambio::app {
namespace {

// A run is paced by the wall clock when any device it uses is on a backend that drives real
// devices.
bool uses_wall_clock_backend(const hal::HardwareInfo& hardware,
                             const hal::BackendFactory& factory) {
  bool paced = false;
  for (const auto& group : hardware.groups) {
    paced |= factory.traits(group.backend).paced_by_wall_clock;
  }
  for (const auto& camera : hardware.cameras) {
    paced |= factory.traits(camera.backend).paced_by_wall_clock;
  }
  for (const auto& sensor : hardware.touch_sensors) {
    paced |= factory.traits(sensor.backend).paced_by_wall_clock;
  }
  return paced;
}

// Backends are deactivated (drives quick-stopped and disabled) however a run ends; the ROS 2
// bridge publishes while they are active, its last message the state the run ended in, and the
// perception link carries pairs and results meanwhile.
template <typename Backends>
struct ActiveBackends {
  ActiveBackends(Backends& all, ros2::Ros2Bridge* ros2_bridge,
                 ros2::RobotPerceptionLink* perception_link)
      : backends(all), bridge(ros2_bridge), link(perception_link) {
    for (auto& [name, backend] : backends) backend->activate();
    if (bridge != nullptr) bridge->start();
    if (link != nullptr) link->start();
  }
  ~ActiveBackends() {
    if (link != nullptr) link->stop();
    if (bridge != nullptr) bridge->stop();
    for (auto& [name, backend] : backends) backend->deactivate();
  }
  ActiveBackends(const ActiveBackends&) = delete;
  ActiveBackends& operator=(const ActiveBackends&) = delete;
  Backends& backends;
  ros2::Ros2Bridge* bridge;
  ros2::RobotPerceptionLink* link;
};

}  // namespace

MainJob::MainJob(const config::ExperimentConfig& experiment, const hal::BackendFactory& factory,
                 MainJobOptions options)
    : experiment_(experiment),
      options_(options),
      hardware_(config::hardware_description(experiment.rig)) {
  check_rig_backends(experiment_.rig, factory);
  realtime_ = uses_wall_clock_backend(hardware_, factory) ||
              experiment_.executor == config::ExecutorKind::kRealtime;
  if (realtime_) {
    executor_ = std::make_unique<runtime::RealtimeExecutor>(
        std::vector<runtime::ScheduledLoop>{},
        runtime::RealtimeOptions{experiment_.rig.runtime.lock_memory, true});
  } else {
    auto lockstep = std::make_unique<runtime::LockstepExecutor>();
    lockstep_ = lockstep.get();
    executor_ = std::move(lockstep);
  }
  build_backends(factory);
  build_loops();
  build_perception_link();  // Before the bridge: its /diagnostics report the link.
  build_ros2_bridge();
}

MainJob::~MainJob() = default;

MainJobResult MainJob::run(const std::atomic<bool>& stop,
                           const std::function<void(double, double)>& progress, double duration_s) {
  MainJobResult result;
  result.realtime = realtime_;
  const double run_s = duration_s < 0.0 ? experiment_.duration_s : duration_s;
  const auto total_ns = static_cast<std::int64_t>(run_s * 1e9);
  const auto wall_start = std::chrono::steady_clock::now();
  auto wall_elapsed_s = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  std::int64_t done_ns = 0;
  if (perception_link_) wait_for_perception_host();
  {
    const ActiveBackends active(backends_, ros2_bridge_.get(), perception_link_.get());
    done_ns =
        executor_->run(stop, total_ns, [&](double done_s) { progress(done_s, wall_elapsed_s()); });
  }
  result.simulated_s = static_cast<double>(done_ns) * 1e-9;
  result.wall_s = wall_elapsed_s();
  result.stopped_by_signal = stop.load();
  collect(result);
  return result;
}

MainJobResult MainJob::run_stepped(const std::atomic<bool>& stop,
                                   const std::function<std::int64_t(std::int64_t)>& next_stop_ns) {
  runtime::LockstepExecutor* lockstep = lockstep_;
  if (lockstep == nullptr) {
    throw std::logic_error("a stepped run needs the lockstep executor");
  }
  MainJobResult result;
  const auto wall_start = std::chrono::steady_clock::now();
  const std::int64_t start_ns = lockstep->clock().now_ns();
  {
    const ActiveBackends active(backends_, ros2_bridge_.get(), perception_link_.get());
    lockstep->configure();
    // Loops are deactivated (drives stopped) even when the caller throws.
    struct Deactivate {
      runtime::LockstepExecutor& executor;
      ~Deactivate() { executor.deactivate(); }
    } deactivate{*lockstep};
    while (!stop.load()) {
      const std::int64_t next_ns = next_stop_ns(lockstep->clock().now_ns());
      if (next_ns < 0) break;
      lockstep->run_until_ns(std::max(next_ns, lockstep->clock().now_ns()));
    }
  }
  result.simulated_s = static_cast<double>(lockstep->clock().now_ns() - start_ns) * 1e-9;
  result.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  result.stopped_by_signal = stop.load();
  collect(result);
  return result;
}

std::int64_t MainJob::control_period_ns() const {
  return static_cast<std::int64_t>(
      std::ceil(1e9 / loop_schedule(experiment_.rig, "control").rate_hz));
}

control::BelievedJoints MainJob::make_believed_joints() const {
  std::vector<control::BelievedJoints::Source> sources;
  for (const auto& slot : joint_loops_) sources.push_back({slot.states.get(), slot.rig_indices});
  return control::BelievedJoints(std::move(sources), static_cast<int>(joint_order_.size()));
}

int MainJob::joint_index(const std::string& joint_name) const {
  for (std::size_t i = 0; i < joint_order_.size(); ++i) {
    if (joint_order_[i] == joint_name) return static_cast<int>(i);
  }
  throw std::runtime_error("joint '" + joint_name + "' is in no joint group");
}

std::size_t MainJob::camera_index(const std::string& camera_name) const {
  for (std::size_t i = 0; i < hardware_.cameras.size(); ++i) {
    if (hardware_.cameras[i].name == camera_name) return i;
  }
  throw std::runtime_error("stereo camera '" + camera_name + "' is not a rig camera");
}

}  // namespace cambio::app
