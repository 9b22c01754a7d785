#include "main_job.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <stdexcept>

#include "cambio/behaviour/attention_behaviour.hpp"
#include "cambio/canopen/can_joint_group.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/control/joint_loop_plan.hpp"
#include "cambio/control/pose_hold_loop.hpp"
#include "cambio/perception/perception_config.hpp"
#include "cambio/runtime/lockstep_executor.hpp"
#include "cambio/runtime/realtime_executor.hpp"
#include "cambio/sim/ground_truth.hpp"
#include "cambio/sim/mjcf_builder.hpp"
#include "cambio/sim/rendered_views.hpp"
#include "controller_params.hpp"
#include "foveation_check.hpp"
#include "rig_backend_check.hpp"
#include "robot_actions.hpp"

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

std::size_t camera_index(const hal::HardwareInfo& hardware, const std::string& name) {
  for (std::size_t i = 0; i < hardware.cameras.size(); ++i) {
    if (hardware.cameras[i].name == name) return i;
  }
  throw std::runtime_error("stereo camera '" + name + "' is not a rig camera");
}

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
}

MainJob::~MainJob() = default;

void MainJob::build_backends(const hal::BackendFactory& factory) {
  const hal::BackendContext context{&executor_->clock(), experiment_.seed, realtime_};
  // One backend instance per backend name, shared by the groups and cameras naming it.
  auto backend_for = [&](const std::string& name,
                         const std::string& requested_by) -> hal::Backend& {
    auto& slot = backends_[name];
    if (!slot) slot = factory.make(name, hardware_, context, requested_by);
    return *slot;
  };
  for (const auto& camera : hardware_.cameras) {
    cameras_.push_back(
        backend_for(camera.backend, "camera '" + camera.name + "'").make_camera(camera.name));
  }
  for (const auto& group : hardware_.groups) {
    groups_.push_back(backend_for(group.backend, "joint group '" + group.name + "'")
                          .make_joint_group(group.name));
    joint_order_.insert(joint_order_.end(), group.joints.begin(), group.joints.end());
  }
  if (backends_.empty()) throw std::runtime_error("the rig names no joint group and no camera");

  // A backend that models the whole robot (the sim) follows every group another backend
  // drives, so its cameras see what those drives did.
  for (auto& group : groups_) driven_groups_.push_back(group.get());
  for (auto& [follower_name, follower] : backends_) {
    if (!follower->follows_other_backends()) continue;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      if (hardware_.groups[g].backend == follower_name) continue;
      taps_.push_back(std::make_unique<hal::JointStateTap>(*driven_groups_[g]));
      follower->follow_group(hardware_.groups[g], *taps_.back());
      driven_groups_[g] = taps_.back().get();
    }
  }
  if (experiment_.task == config::ControlTask::kGaze) make_touch_sensors();
  for (auto& [name, backend] : backends_) backend->configure();
  for (auto& [name, backend] : backends_) backend->offer(offers_);
}

void MainJob::make_touch_sensors() {
  // An arm reaches when its group is shaped as control::ArmChain and its gripper carries a touch
  // sensor; its side is where its shoulder is (y > 0: left).
  for (const auto& sensor : hardware_.touch_sensors) {
    const hal::JointInfo* gripper = hardware_.find_joint(sensor.parent);
    const auto backend = backends_.find(sensor.backend);
    if (gripper == nullptr || backend == backends_.end()) continue;
    control::ArmChain chain;
    try {
      chain = control::find_arm_chain(hardware_, gripper->group);
    } catch (const std::invalid_argument& error) {
      std::cerr << "cambio: warning: touch sensor '" << sensor.name << "': " << error.what()
                << "; that arm does not reach\n";
      continue;
    }
    if (chain.names[4] != sensor.parent) continue;
    const std::size_t side = chain.shoulder_W.y() > 0.0 ? 0 : 1;
    if (touch_sensors_[side]) continue;
    touch_sensors_[side] = backend->second->make_touch_sensor(sensor.name);
    arm_groups_[side] = gripper->group;
  }
}

void MainJob::build_arm_loop(const control::JointTargetFrame& pose,
                             std::vector<control::BelievedJoints::Source> sources) {
  if (arm_groups_[0].empty() && arm_groups_[1].empty()) return;
  arm_loop_ = std::make_unique<control::ArmReachLoop>(
      hardware_, arm_reach_params(experiment_, arm_groups_), pose,
      control::BelievedJoints(std::move(sources), static_cast<int>(joint_order_.size())),
      &gaze_loop_->status(), arm_commands_,
      std::array<hal::TouchSensor*, 2>{touch_sensors_[0].get(), touch_sensors_[1].get()});
  // The gaze loop publishes every joint's target: it takes the arms' from the arm loop, which
  // runs before it in each control tick (same rate and priority run in the order added).
  gaze_loop_->set_overlay(&arm_loop_->targets(), arm_loop_->arm_rig_indices());
  executor_->add_loop({arm_loop_.get(), loop_schedule(experiment_.rig, "control")});
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
        hal::CommandMode::kPosition, hardware_.find_joint(joint_name)->initial_position_rad};
  }
  // One joint loop per group rate; each takes its joints' targets from the rig-wide frame.
  const runtime::LoopSchedule joint_schedule = loop_schedule(rig, "joint");
  const auto plans = control::plan_joint_loops(hardware_.groups, joint_schedule.rate_hz);
  std::vector<int> first_joint_of_group;
  for (int first = 0; const auto& group : hardware_.groups) {
    first_joint_of_group.push_back(first);
    first += static_cast<int>(group.joints.size());
  }
  for (const auto& plan : plans) {
    control::JointLoopParams params = joint_loop_params(rig);
    params.fault_recovery_delay_s = experiment_.fault_recovery.after_s;
    params.max_fault_recoveries = experiment_.fault_recovery.max_recoveries;
    params.name = plan.name;
    params.target_count = static_cast<int>(joint_order_.size());
    if (plans.size() > 1) params.rig_hold = &rig_hold_;
    std::vector<hal::JointGroup*> loop_groups;
    for (const std::size_t g : plan.groups) {
      loop_groups.push_back(driven_groups_[g]);
      for (std::size_t j = 0; j < hardware_.groups[g].joints.size(); ++j) {
        params.target_indices.push_back(first_joint_of_group[g] + static_cast<int>(j));
      }
    }
    JointLoopSlot slot;
    slot.rig_indices = params.target_indices;
    slot.states = std::make_unique<hal::SeqlockChannel<control::JointStateFrame>>();
    slot.loop = std::make_unique<control::JointLoop>(std::move(loop_groups), targets_, *slot.states,
                                                     std::move(params));
    runtime::LoopSchedule schedule = joint_schedule;
    schedule.rate_hz = plan.rate_hz;
    executor_->add_loop({slot.loop.get(), schedule});
    joint_loops_.push_back(std::move(slot));
  }

  std::vector<hal::Camera*> cameras;
  for (const auto& camera : cameras_) cameras.push_back(camera.get());
  std::optional<perception::StereoPairIndices> stereo;
  if (hardware_.stereo) {
    stereo = perception::StereoPairIndices{camera_index(hardware_, hardware_.stereo->left_camera),
                                           camera_index(hardware_, hardware_.stereo->right_camera)};
  }
  camera_loop_ = std::make_unique<perception::CameraLoop>(cameras, stereo);

  // Perception runs whenever the rig has a stereo pair.
  perception::SsmConfig ssm;
  if (stereo) {
    const std::string ssm_path = experiment_.perception_path.empty()
                                     ? perception::default_ssm_config_path()
                                     : experiment_.perception_path;
    ssm = ssm_path.empty() ? perception::SsmConfig{} : perception::load_ssm_config(ssm_path, {});
    if (!(ssm.disparity.scan_range_px > 0.0)) {
      ssm.disparity.scan_range_px = perception::largest_disparity_px(
          hardware_.cameras[stereo->left].intrinsics.focal_x_px, hardware_.stereo->baseline_m);
    }
    for (const std::size_t eye : {stereo->left, stereo->right}) {
      const config::CameraConfig* camera = rig.find_camera(hardware_.cameras[eye].name);
      if (camera == nullptr) continue;
      for (const std::string& warning : foveation_warnings(*camera, ssm)) {
        std::cerr << "cambio: warning: " << warning << "\n";
      }
    }
    perception_loop_ = std::make_unique<perception::SsmServer>(
        "perception", camera_loop_->stereo_frames(), hardware_.cameras[stereo->left],
        hardware_.cameras[stereo->right], ssm);
  }

  if (experiment_.task == config::ControlTask::kGaze) {
    if (!perception_loop_) throw std::runtime_error("the gaze task needs a stereo rig");
    std::vector<control::BelievedJoints::Source> sources;
    for (const auto& slot : joint_loops_) sources.push_back({slot.states.get(), slot.rig_indices});
    auto loop = std::make_unique<control::GazeLoop>(
        hardware_, gaze_loop_params(experiment_, hardware_), pose,
        control::BelievedJoints(sources, static_cast<int>(joint_order_.size())),
        perception_loop_->summaries(), perception_loop_->requests(), gaze_commands_, targets_);
    gaze_loop_ = loop.get();
    gaze_loop_->set_extra_features(&feature_requests_);
    control_loop_ = std::move(loop);
    // The script runs at the control rate, before the gaze loop in each lockstep tick. A
    // behaviour takes its place as the gaze commands' writer (the loader allows only one).
    const bool has_arms = !arm_groups_[0].empty() || !arm_groups_[1].empty();
    if (options_.send_script && !experiment_.behaviour) {
      // Without arms an arm entry would go to a channel nobody reads: the script refuses it.
      script_ = std::make_unique<control::CommandScript>(
          command_script(experiment_), gaze_commands_, has_arms ? &arm_commands_ : nullptr);
      executor_->add_loop({script_.get(), loop_schedule(rig, "control")});
    }
    build_arm_loop(pose, std::move(sources));
    build_actions();
  } else {
    control_loop_ = std::make_unique<control::PoseHoldLoop>(pose, targets_);
  }

  executor_->add_loop({control_loop_.get(), loop_schedule(rig, "control")});
  build_trace();
  executor_->add_loop({camera_loop_.get(), loop_schedule(rig, "camera")});
  if (perception_loop_) {
    executor_->add_loop({perception_loop_.get(), loop_schedule(rig, "perception")});
  }
  // After the perception loop: it reads the SSM's frames, which exist once that is configured.
  if (experiment_.behaviour) build_behaviour(ssm);
  for (auto& [name, backend] : backends_) {
    for (const hal::BackendLoop& backend_loop : backend->loops()) {
      executor_->add_loop(
          {backend_loop.loop, runtime::LoopSchedule{backend_loop.rate_hz, backend_loop.priority}});
    }
  }
}

void MainJob::build_actions() {
  // One set of actions for whoever commands the robot (a behaviour, the console): they write
  // the loops' single-writer channels under one lock.
  const hal::Eye dominant = experiment_.gaze.dominant_eye;
  const hal::CameraInfo* eye = hardware_.find_camera(
      dominant == hal::Eye::kLeft ? hardware_.stereo->left_camera : hardware_.stereo->right_camera);
  RobotActions::Setup setup;
  setup.rig_joint_order = joint_order_;
  setup.head_joints = head_joint_names();
  setup.image_width_px = eye->intrinsics.width_px;
  setup.image_height_px = eye->intrinsics.height_px;
  actions_ = std::make_unique<RobotActions>(
      hardware_, std::move(setup),
      RobotActions::Channels{&gaze_commands_, arm_loop_ ? &arm_commands_ : nullptr,
                             &feature_requests_});
}

void MainJob::build_behaviour(const perception::SsmConfig& ssm) {
  const config::BehaviourConfig& config = *experiment_.behaviour;
  // The loader allows a behaviour with the gaze task only, which needs the stereo pair.
  if (gaze_loop_ == nullptr || !perception_loop_) {
    throw BehaviourSetupError("behaviour '" + config.name + "': needs the gaze task");
  }
  plugins_ = std::make_unique<behaviour::PluginLibraries>();
  registry_ = std::make_unique<behaviour::BehaviourRegistry>();
  behaviour::register_builtin_behaviours(*registry_);
  try {
    for (const std::string& path : config.plugins) plugins_->load(path, *registry_);
    std::map<std::string, behaviour::BehaviourParams::Entry, std::less<>> entries;
    for (const auto& param : config.params) entries[param.key] = {param.text, param.where};
    behaviour::BehaviourParams params(std::move(entries), "behaviour.params");
    behaviour_ = registry_->make(config.name, params);
  } catch (const std::exception& error) {
    throw BehaviourSetupError(experiment_.source_file + ": behaviour: " + error.what());
  }
  const hal::Eye dominant = experiment_.gaze.dominant_eye;
  behaviour::BehaviourLoopSources sources;
  sources.ssm = &perception_loop_->summaries();
  sources.ssm_frames = [server = perception_loop_.get()] { return &server->frames(); };
  sources.gaze = &gaze_loop_->status();
  if (arm_loop_) sources.arms = &arm_loop_->status();
  for (const auto& spec : perception::feature_map_specs(ssm.operators)) {
    sources.feature_map_names.push_back(spec.name);
  }
  std::vector<control::BelievedJoints::Source> believed;
  for (const auto& slot : joint_loops_) believed.push_back({slot.states.get(), slot.rig_indices});
  behaviour_loop_ = std::make_unique<behaviour::BehaviourLoop>(
      "behaviour", hardware_, dominant, std::move(sources),
      control::BelievedJoints(std::move(believed), static_cast<int>(joint_order_.size())),
      *behaviour_, *actions_);
  // Decision making, not control: never at a real-time priority or pinned beside the loops.
  executor_->add_loop({behaviour_loop_.get(), runtime::LoopSchedule{config.rate_hz, 0, -1}});
}

void MainJob::build_trace() {
  // The trace needs the world's ground truth (a simulator's) and something to look with.
  sim::GroundTruth* truth = ground_truth();
  if (!options_.record_trace || truth == nullptr || !hardware_.stereo || !perception_loop_) return;
  hal::Eye dominant = hal::Eye::kLeft;
  if (experiment_.task == config::ControlTask::kGaze) dominant = experiment_.gaze.dominant_eye;
  const auto camera_of = [&](hal::Eye eye) -> const hal::CameraInfo& {
    return *hardware_.find_camera(eye == hal::Eye::kLeft ? hardware_.stereo->left_camera
                                                         : hardware_.stereo->right_camera);
  };
  TraceSources sources;
  sources.joint_names = joint_order_;
  sources.targets = &targets_;
  for (const auto& slot : joint_loops_)
    sources.believed.push_back({slot.states.get(), slot.rig_indices});
  sources.gaze = gaze_loop_ != nullptr ? &gaze_loop_->status() : nullptr;
  sources.ssm = &perception_loop_->summaries();
  sources.truth = truth;
  sources.dominant_camera = camera_of(dominant).name;
  sources.verging_camera = camera_of(hal::other(dominant)).name;
  sources.verging_focal_px = camera_of(hal::other(dominant)).intrinsics.focal_x_px;
  sources.verging_eye_is_right = hal::other(dominant) == hal::Eye::kRight;
  sources.dominant_pan_joint = camera_of(dominant).parent_frame;
  sources.verging_pan_joint = camera_of(hal::other(dominant)).parent_frame;
  sources.target_object = experiment_.evaluation.target_object;
  sources.key_frame_times_s = experiment_.evaluation.key_frames_s;
  sources.visit_objects = experiment_.evaluation.visit_objects;
  if (arm_loop_) {
    sources.arms = &arm_loop_->status();
    for (int side = 0; side < 2; ++side) {
      if (const control::ArmChain* chain = arm_loop_->arm(side)) {
        sources.arm_chains[static_cast<std::size_t>(side)] = *chain;
      }
    }
  }
  // At the control rate, but as evaluation: never at a real-time priority or pinned beside the
  // loops it watches (its ground-truth queries and key-frame renders take milliseconds).
  runtime::LoopSchedule schedule = loop_schedule(experiment_.rig, "control");
  schedule.priority = 0;
  schedule.cpu = -1;
  trace_ =
      std::make_unique<TraceRecorder>(std::move(sources), schedule.rate_hz, experiment_.duration_s);
  executor_->add_loop({trace_.get(), schedule});
}

std::vector<std::string> MainJob::head_joint_names() const {
  std::vector<std::string> names;
  if (!hardware_.stereo) return names;
  // Up the left eye's chain (eye pan, eye tilt, neck tilt, neck pan), then the right eye's pan.
  std::vector<std::string> chain;
  for (const std::string* link =
           &hardware_.find_camera(hardware_.stereo->left_camera)->parent_frame;
       *link != "base";) {
    const hal::JointInfo* joint = hardware_.find_joint(*link);
    if (joint == nullptr) break;
    chain.insert(chain.begin(), joint->name);
    link = &joint->parent;
  }
  names = chain;
  const std::string& right_pan =
      hardware_.find_camera(hardware_.stereo->right_camera)->parent_frame;
  if (std::find(names.begin(), names.end(), right_pan) == names.end()) names.push_back(right_pan);
  return names;
}

namespace {

// Backends are deactivated (drives quick-stopped and disabled) however a run ends.
template <typename Backends>
struct ActiveBackends {
  explicit ActiveBackends(Backends& all) : backends(all) {
    for (auto& [name, backend] : backends) backend->activate();
  }
  ~ActiveBackends() {
    for (auto& [name, backend] : backends) backend->deactivate();
  }
  ActiveBackends(const ActiveBackends&) = delete;
  ActiveBackends& operator=(const ActiveBackends&) = delete;
  Backends& backends;
};

}  // namespace

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
  {
    const ActiveBackends active(backends_);
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
    const ActiveBackends active(backends_);
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

sim::GroundTruth* MainJob::ground_truth() {
  return offers_.find<sim::GroundTruth>();
}

void MainJob::collect(MainJobResult& result) {
  result.realtime = realtime_;
  result.loops = executor_->statistics();
  result.camera_frames = camera_loop_->frames_grabbed();
  result.stereo_pairs = camera_loop_->pairs_published();
  for (const auto& joint_loop : joint_loops_) {
    result.watchdog_cycles += joint_loop.loop->stale_cycles();
    result.startup_hold_cycles += joint_loop.loop->awaiting_targets_cycles();
    result.fault_hold_cycles += joint_loop.loop->fault_hold_cycles();
    result.fault_recoveries += joint_loop.loop->fault_recoveries();
    control::JointStateFrame states;
    if (joint_loop.states->read(states)) result.fault_latched_at_end |= states.fault_latched;
  }
  if (perception_loop_) {
    result.mismatched_stereo_pairs = perception_loop_->mismatched_pairs();
    perception::SsmSummary summary;
    if (perception_loop_->summaries().read(summary)) result.perception = summary;
  }
  if (gaze_loop_ != nullptr) {
    control::GazeStatus status;
    if (gaze_loop_->status().read(status)) result.gaze = status;
    result.gaze_rejected_commands = gaze_loop_->rejected_commands();
    result.gaze_corrections = gaze_loop_->corrections();
    result.gaze_measurements = gaze_loop_->measurements();
    if (script_) {
      result.script_start_ns = script_->start_ns();
      for (const std::int64_t sent_ns : script_->sent_ns()) {
        result.command_sent_s.push_back(
            sent_ns < 0 ? -1.0 : static_cast<double>(sent_ns - script_->start_ns()) * 1e-9);
      }
    }
  }
  if (behaviour_loop_) {
    BehaviourReport report;
    report.name = experiment_.behaviour->name;
    report.plugins = plugins_->paths();
    report.steps = behaviour_loop_->steps();
    report.status = behaviour_loop_->status();
    report.failed = behaviour_loop_->failed();
    report.error = behaviour_loop_->error();
    result.behaviour = std::move(report);
  }
  if (arm_loop_) {
    control::ArmStatus status;
    if (arm_loop_->status().read(status)) result.arms = status;
    for (int side = 0; side < 2; ++side) {
      result.arm_present[static_cast<std::size_t>(side)] = arm_loop_->arm(side) != nullptr;
    }
  }
  const auto can_groups = offers_.all<const canopen::CanJointGroup>();
  for (const auto& group : hardware_.groups) {  // Rig order.
    for (const canopen::CanJointGroup* can_group : can_groups) {
      if (can_group->info().name == group.name) {
        result.can_groups.push_back({group.name, can_group->counters()});
      }
    }
  }
  result.renderer = renderer();
}

std::optional<sim::RendererDescription> MainJob::renderer() const {
  for (const sim::RenderedViews* views : offers_.all<sim::RenderedViews>()) {
    if (auto description = views->renderer()) return description;
  }
  return std::nullopt;
}

std::vector<hal::Image> MainJob::last_frames() {
  std::vector<const hal::Image*> frames(cameras_.size(), nullptr);
  if (camera_loop_->has_stereo()) {
    // The loops have stopped: this thread may take the stereo channel's reader side.
    auto& pairs = camera_loop_->stereo_frames();
    pairs.acquire();
    const auto& stereo = *hardware_.stereo;
    frames[camera_index(hardware_, stereo.left_camera)] = &pairs.front().left;
    frames[camera_index(hardware_, stereo.right_camera)] = &pairs.front().right;
  }
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (frames[i] != nullptr) continue;
    auto& channel = camera_loop_->frames(i);
    channel.acquire();
    frames[i] = &channel.front();
  }
  std::vector<hal::Image> images;
  images.reserve(frames.size());
  const auto renderers = offers_.all<sim::RenderedViews>();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    images.push_back(*frames[i]);
    if (frames[i]->sequence == 0) continue;
    for (sim::RenderedViews* views : renderers) {
      hal::Image whole;
      if (!views->render_whole_frame(hardware_.cameras[i].name, whole)) continue;
      whole.sequence = frames[i]->sequence;
      images.back() = std::move(whole);
      break;
    }
  }
  return images;
}

}  // namespace cambio::app
