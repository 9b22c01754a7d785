#include "main_job.hpp"

#include <stdexcept>

#include "controller_params.hpp"

// MainJob's control loops: the gaze loop with the script and the arms when the task is gaze,
// a pose hold otherwise. They write the rig-wide targets the joint loops read.

namespace cambio::app {

void MainJob::build_control_loop(const control::JointTargetFrame& pose) {
  if (experiment_.task == config::ControlTask::kGaze) {
    build_gaze_loop(pose);
  } else {
    auto loop = std::make_unique<control::PoseHoldLoop>(
        hardware_, pose, make_believed_joints(),
        max_tracking_errors_rad(experiment_.rig, hardware_), targets_);
    pose_hold_ = loop.get();
    control_loop_ = std::move(loop);
  }
  executor_->add_loop({control_loop_.get(), loop_schedule(experiment_.rig, "control")});
}

void MainJob::build_gaze_loop(const control::JointTargetFrame& pose) {
  if (ssm_summaries() == nullptr) throw std::runtime_error("the gaze task needs a stereo rig");
  std::vector<control::BelievedJoints::Source> sources;
  for (const auto& slot : joint_loops_) sources.push_back({slot.states.get(), slot.rig_indices});
  auto loop = std::make_unique<control::GazeLoop>(
      hardware_, gaze_loop_params(experiment_, hardware_), pose,
      control::BelievedJoints(sources, static_cast<int>(joint_order_.size())), *ssm_summaries(),
      *ssm_requests(), gaze_commands_, targets_);
  gaze_loop_ = loop.get();
  gaze_loop_->set_extra_features(&feature_requests_);
  gaze_loop_->set_trajectories(&head_trajectories_);
  control_loop_ = std::move(loop);
  // The script runs at the control rate, before the gaze loop in each lockstep tick. A
  // behaviour takes its place as the gaze commands' writer (the loader allows only one).
  const bool has_arms = !arm_groups_[0].empty() || !arm_groups_[1].empty();
  if (options_.send_script && !experiment_.behaviour) {
    // Without arms an arm entry would go to a channel nobody reads: the script refuses it.
    script_ = std::make_unique<control::CommandScript>(command_script(experiment_), gaze_commands_,
                                                       has_arms ? &arm_commands_ : nullptr);
    executor_->add_loop({script_.get(), loop_schedule(experiment_.rig, "control")});
  }
  build_arm_loop(pose, std::move(sources));
  build_actions();
}

void MainJob::build_arm_loop(const control::JointTargetFrame& pose,
                             std::vector<control::BelievedJoints::Source> sources) {
  if (arm_groups_[0].empty() && arm_groups_[1].empty()) return;
  arm_loop_ = std::make_unique<control::ArmReachLoop>(
      hardware_, arm_reach_params(experiment_, hardware_, arm_groups_), pose,
      control::BelievedJoints(std::move(sources), static_cast<int>(joint_order_.size())),
      &gaze_loop_->status(), arm_commands_,
      std::array<hal::TouchSensor*, 2>{touch_sensors_[0].get(), touch_sensors_[1].get()});
  // The gaze loop publishes every joint's target: it takes the arms' from the arm loop, which
  // runs before it in each control tick (same rate and priority run in the order added).
  gaze_loop_->set_overlay(&arm_loop_->targets(), arm_loop_->arm_rig_indices());
  arm_loop_->set_trajectories(&arm_trajectories_);
  executor_->add_loop({arm_loop_.get(), loop_schedule(experiment_.rig, "control")});
}

}  // namespace cambio::app
