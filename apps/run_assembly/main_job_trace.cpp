#include "main_job.hpp"

#include <algorithm>

#include "cambio/sim/ground_truth.hpp"
#include "controller_params.hpp"

// MainJob's evaluation trace (believed vs true at the control rate) and the head joints its plots
// show.

namespace cambio::app {

void MainJob::build_trace() {
  // The trace needs the world's ground truth (a simulator's) and something to look with.
  sim::GroundTruth* truth = ground_truth();
  if (!options_.record_trace || truth == nullptr || !hardware_.stereo || ssm_summaries() == nullptr)
    return;
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
  sources.ssm = ssm_summaries();
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

}  // namespace cambio::app
