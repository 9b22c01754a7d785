#include "main_job.hpp"

#include <chrono>
#include <stdexcept>

#include "cambio/hal/manual_clock.hpp"
#include "cambio/perception/perception_config.hpp"
#include "cambio/runtime/lockstep_executor.hpp"
#include "cambio/runtime/realtime_executor.hpp"

namespace cambio::app {
namespace {

// The joint loop holds position if the control loop's targets are older than this.
constexpr double kCommandTimeoutS = 0.1;

/// The control loop when the task is to hold the initial pose: the joint loop's limits, rate
/// limits and watchdog still act on every cycle.
class PoseHoldLoop final : public hal::Loop {
 public:
  PoseHoldLoop(control::JointTargetFrame pose, hal::SeqlockChannel<control::JointTargetFrame>& out)
      : pose_(pose), out_(out) {}
  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    pose_.stamp_ns = tick.now_ns;
    out_.write(pose_);
    return hal::Status::kOk;
  }

 private:
  std::string name_ = "control";
  control::JointTargetFrame pose_;
  hal::SeqlockChannel<control::JointTargetFrame>& out_;
};

const config::LoopConfig& loop_schedule(const config::RigConfig& rig, const std::string& name) {
  const config::LoopConfig* loop = rig.find_loop(name);
  if (loop == nullptr) throw std::runtime_error("the rig defines no '" + name + "' loop");
  return *loop;
}

}  // namespace

MainJob::MainJob(const config::ExperimentConfig& experiment, const hal::BackendFactory& factory)
    : experiment_(experiment) {
  build_backends(factory);
  build_loops();
}

MainJob::~MainJob() = default;

void MainJob::build_backends(const hal::BackendFactory& factory) {
  const config::RigConfig& rig = experiment_.rig;
  const hal::BackendOptions options{experiment_.scene_path, experiment_.seed,
                                    experiment_.executor == config::ExecutorKind::kRealtime};
  // One backend instance per backend name, shared by the groups and cameras naming it.
  auto backend_for = [&](const std::string& name,
                         const std::string& requested_by) -> hal::Backend& {
    auto& slot = backends_[name];
    if (!slot) slot = factory.make(name, rig, options, requested_by);
    return *slot;
  };
  for (const auto& group : rig.groups) {
    groups_.push_back(backend_for(group.backend, "joint group '" + group.name + "'")
                          .make_joint_group(group.name));
    joint_order_.insert(joint_order_.end(), group.joints.begin(), group.joints.end());
  }
  for (const auto& camera : rig.cameras) {
    cameras_.push_back(
        backend_for(camera.backend, "camera '" + camera.name + "'").make_camera(camera.name));
  }
  if (backends_.empty()) throw std::runtime_error("the rig names no joint group and no camera");
}

int MainJob::joint_index(const std::string& joint_name) const {
  for (std::size_t i = 0; i < joint_order_.size(); ++i) {
    if (joint_order_[i] == joint_name) return static_cast<int>(i);
  }
  throw std::runtime_error("joint '" + joint_name + "' is in no joint group");
}

void MainJob::build_loops() {
  const config::RigConfig& rig = experiment_.rig;

  control::JointTargetFrame pose;
  for (const auto& joint_name : joint_order_) {
    pose.commands[static_cast<std::size_t>(pose.count++)] = {
        hal::CommandMode::kPosition, rig.find_joint(joint_name)->initial_position_rad};
  }
  std::vector<hal::JointGroup*> groups;
  for (const auto& group : groups_) groups.push_back(group.get());
  joint_loop_ = std::make_unique<control::JointLoop>(groups, targets_, states_, kCommandTimeoutS);

  std::vector<hal::Camera*> cameras;
  for (const auto& camera : cameras_) cameras.push_back(camera.get());
  camera_loop_ = std::make_unique<CameraLoop>(cameras);
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    frame_readers_.push_back(
        std::make_unique<LatestFrameCamera>(cameras_[i]->info(), camera_loop_->frames(i)));
  }

  // Perception runs whenever the rig has a stereo pair.
  auto camera_index = [&](const std::string& name) {
    for (std::size_t i = 0; i < rig.cameras.size(); ++i) {
      if (rig.cameras[i].name == name) return i;
    }
    throw std::runtime_error("stereo camera '" + name + "' is not a rig camera");
  };
  if (rig.stereo) {
    const std::string ssm_path = experiment_.perception_path.empty()
                                     ? perception::default_ssm_config_path()
                                     : experiment_.perception_path;
    const perception::SsmConfig ssm =
        ssm_path.empty() ? perception::SsmConfig{} : perception::load_ssm_config(ssm_path, {});
    perception_loop_ = std::make_unique<perception::SsmServer>(
        "perception", *frame_readers_[camera_index(rig.stereo->left_camera)],
        *frame_readers_[camera_index(rig.stereo->right_camera)], ssm);
  }

  if (experiment_.task == config::ControlTask::kVergence) {
    if (!perception_loop_) throw std::runtime_error("the vergence task needs a stereo rig");
    const bool right_verges = experiment_.vergence.verging_eye == hal::Eye::kRight;
    const auto& verging_camera =
        *rig.find_camera(right_verges ? rig.stereo->right_camera : rig.stereo->left_camera);
    const auto& dominant_camera =
        *rig.find_camera(right_verges ? rig.stereo->left_camera : rig.stereo->right_camera);
    control::VergenceParams params;
    params.verging_eye = experiment_.vergence.verging_eye;
    params.focal_px = verging_camera.focal_x_px;
    params.gain = experiment_.vergence.gain;
    params.min_confidence = experiment_.vergence.min_confidence;
    params.max_step_rad = experiment_.vergence.max_step_rad;
    auto loop = std::make_unique<control::VergenceLoop>(
        control::VergenceController(params), pose, joint_index(verging_camera.parent),
        joint_index(dominant_camera.parent), perception_loop_->summaries(), targets_);
    vergence_loop_ = loop.get();
    control_loop_ = std::move(loop);
  } else {
    control_loop_ = std::make_unique<PoseHoldLoop>(pose, targets_);
  }
}

MainJobResult MainJob::run(const std::atomic<bool>& stop,
                           const std::function<void(double, double)>& progress) {
  const config::RigConfig& rig = experiment_.rig;
  std::vector<runtime::ScheduledLoop> scheduled = {
      {joint_loop_.get(), loop_schedule(rig, "joint")},
      {control_loop_.get(), loop_schedule(rig, "control")},
      {camera_loop_.get(), loop_schedule(rig, "camera")},
  };
  if (perception_loop_)
    scheduled.push_back({perception_loop_.get(), loop_schedule(rig, "perception")});
  for (auto& [name, backend] : backends_) {
    for (const hal::BackendLoop& backend_loop : backend->loops()) {
      config::LoopConfig schedule;
      schedule.name = backend_loop.loop->name();
      schedule.rate_hz = backend_loop.rate_hz;
      schedule.priority = backend_loop.priority;
      scheduled.push_back({backend_loop.loop, schedule});
    }
  }

  MainJobResult result;
  hal::Clock& clock = backends_.begin()->second->clock();
  const auto total_ns = static_cast<std::int64_t>(experiment_.duration_s * 1e9);
  const auto wall_start = std::chrono::steady_clock::now();
  auto wall_elapsed_s = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };

  if (experiment_.executor == config::ExecutorKind::kRealtime) {
    runtime::RealtimeExecutor executor(clock, scheduled, {rig.runtime.lock_memory});
    const std::int64_t start_ns = clock.now_ns();
    executor.run(stop, total_ns);
    result.loops = executor.statistics();
    result.simulated_s = static_cast<double>(clock.now_ns() - start_ns) * 1e-9;
  } else {
    auto* sim_clock = dynamic_cast<hal::ManualClock*>(&clock);
    if (sim_clock == nullptr) {
      throw std::runtime_error("the lockstep executor needs simulated time, but backend '" +
                               backends_.begin()->first +
                               "' runs on the wall clock; set experiment.executor: realtime");
    }
    runtime::LockstepExecutor executor(*sim_clock, scheduled);
    executor.configure();
    const std::int64_t start_ns = sim_clock->now_ns();
    constexpr std::int64_t kChunkNs = 100'000'000;
    std::int64_t done = 0;
    while (done < total_ns && !stop.load()) {
      done = std::min(total_ns, done + kChunkNs);
      executor.run_until_ns(start_ns + done);
      progress(static_cast<double>(done) * 1e-9, wall_elapsed_s());
    }
    executor.deactivate();
    result.loops = executor.statistics();
    result.simulated_s = static_cast<double>(done) * 1e-9;
  }
  result.wall_s = wall_elapsed_s();
  result.stopped_by_signal = stop.load();
  result.camera_frames = camera_loop_->frames_grabbed();
  result.watchdog_cycles = joint_loop_->stale_cycles();
  if (perception_loop_) {
    perception::SsmSummary summary;
    perception_loop_->summaries().read(summary);
    result.perception = summary;
  }
  if (vergence_loop_ != nullptr) {
    control::VergenceStatus status;
    vergence_loop_->status().read(status);
    result.vergence = status;
  }
  return result;
}

std::vector<const hal::Image*> MainJob::last_frames() {
  std::vector<const hal::Image*> frames;
  for (const auto& reader : frame_readers_) frames.push_back(&reader->newest_frame());
  return frames;
}

}  // namespace cambio::app
