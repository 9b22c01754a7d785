#include "main_job.hpp"

#include <map>

#include "cambio/behaviour/attention_behaviour.hpp"
#include "robot_actions.hpp"

// MainJob's robot actions and the experiment's behaviour, which commands the robot through them.

namespace cambio::app {

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
                             &feature_requests_, &head_trajectories_,
                             arm_loop_ ? &arm_trajectories_ : nullptr});
  std::vector<control::BelievedJoints::Source> measured;
  for (const auto& slot : joint_loops_) measured.push_back({slot.states.get(), slot.rig_indices});
  actions_->set_measured_joints(
      control::BelievedJoints(std::move(measured), static_cast<int>(joint_order_.size())));
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

}  // namespace cambio::app
