#include "main_job.hpp"

#include <algorithm>
#include <iostream>
#include <stdexcept>

#include "cambio/control/joint_loop_plan.hpp"
#include "controller_params.hpp"
#include "stereo_ssm_config.hpp"

// MainJob's loops and the order the executor is given them; the control loops (gaze, arms) are
// built in main_job_control.cpp.

namespace cambio::app {
namespace {

// Every joint held where the rig description starts it, in rig order.
control::JointTargetFrame initial_pose(const hal::HardwareInfo& hardware,
                                       const std::vector<std::string>& joint_order) {
  control::JointTargetFrame pose;
  for (const auto& joint_name : joint_order) {
    pose.commands[static_cast<std::size_t>(pose.count++)] = {
        hal::CommandMode::kPosition, hardware.find_joint(joint_name)->initial_position_rad};
  }
  return pose;
}

}  // namespace

void MainJob::build_loops() {
  const config::RigConfig& rig = experiment_.rig;
  const control::JointTargetFrame pose = initial_pose(hardware_, joint_order_);
  build_joint_loops();
  const perception::SsmConfig ssm = build_camera_and_perception_loops();
  build_control_loop(pose);
  build_trace();
  // Loops of the same rate and priority run in the order added: the camera and perception loops,
  // made early because the control loop reads their channels, are added after it and the trace.
  executor_->add_loop({camera_loop_.get(), loop_schedule(rig, "camera")});
  if (perception_loop_) {
    executor_->add_loop({perception_loop_.get(), loop_schedule(rig, "perception")});
  }
  // After the perception loop: it reads the SSM's frames, which exist once that is configured.
  if (experiment_.behaviour) build_behaviour(ssm);
  add_backend_loops();
}

void MainJob::build_joint_loops() {
  const config::RigConfig& rig = experiment_.rig;
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
    params.home_after_reboot = experiment_.fault_recovery.home_after_reboot;
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
}

perception::SsmConfig MainJob::build_camera_and_perception_loops() {
  std::vector<hal::Camera*> cameras;
  for (const auto& camera : cameras_) cameras.push_back(camera.get());
  std::optional<perception::StereoPairIndices> stereo;
  if (hardware_.stereo) {
    stereo = perception::StereoPairIndices{camera_index(hardware_.stereo->left_camera),
                                           camera_index(hardware_.stereo->right_camera)};
  }
  camera_loop_ = std::make_unique<perception::CameraLoop>(cameras, stereo);

  // Perception runs whenever the rig has a stereo pair: here, or on the perception host.
  perception::SsmConfig ssm;
  perception_remote_ = stereo && experiment_.ros2 &&
                       experiment_.ros2->split == config::Ros2Config::Split::kPerceptionRemote;
  if (stereo && !perception_remote_) {
    ssm = stereo_ssm_config(experiment_, hardware_, stereo->left, stereo->right);
    perception_loop_ = std::make_unique<perception::SsmServer>(
        "perception", camera_loop_->stereo_frames(), hardware_.cameras[stereo->left],
        hardware_.cameras[stereo->right], ssm);
  }
  return ssm;
}

void MainJob::add_backend_loops() {
  for (auto& [name, backend] : backends_) {
    for (const hal::BackendLoop& backend_loop : backend->loops()) {
      executor_->add_loop(
          {backend_loop.loop, runtime::LoopSchedule{backend_loop.rate_hz, backend_loop.priority}});
    }
  }
}

bool MainJob::request_home(const std::string& joint) {
  if (joint.empty()) {
    for (const auto& slot : joint_loops_) slot.loop->request(hal::DriveRequest::kHome);
    return true;
  }
  const auto it = std::find(joint_order_.begin(), joint_order_.end(), joint);
  if (it == joint_order_.end()) return false;
  const auto rig_index = static_cast<int>(it - joint_order_.begin());
  for (const auto& slot : joint_loops_) {
    const auto local = std::find(slot.rig_indices.begin(), slot.rig_indices.end(), rig_index);
    if (local != slot.rig_indices.end()) {
      return slot.loop->request_home(static_cast<int>(local - slot.rig_indices.begin()));
    }
  }
  return false;
}

std::uint64_t MainJob::homes_refused() const {
  std::uint64_t refused = 0;
  for (const auto& slot : joint_loops_) refused += slot.loop->homes_refused();
  return refused;
}

std::string MainJob::last_refused_home() const {
  for (const auto& slot : joint_loops_) {
    const int local = slot.loop->last_refused_home();
    if (local >= 0)
      return joint_order_[static_cast<std::size_t>(
          slot.rig_indices[static_cast<std::size_t>(local)])];
  }
  return "";
}

}  // namespace cambio::app
