#include "controller_params.hpp"

#include <stdexcept>

namespace cambio::app {

namespace {

const config::LoopConfig& find_loop(const config::RigConfig& rig, const std::string& name) {
  const config::LoopConfig* loop = rig.find_loop(name);
  if (loop == nullptr) throw std::runtime_error("the rig defines no '" + name + "' loop");
  return *loop;
}

}  // namespace

runtime::LoopSchedule schedule_of(const config::LoopConfig& loop) {
  return {loop.rate_hz, loop.priority, loop.cpu,
          loop.overrun == config::OverrunPolicy::kCatchUp ? runtime::OverrunPolicy::kCatchUp
                                                          : runtime::OverrunPolicy::kSkip};
}

runtime::LoopSchedule loop_schedule(const config::RigConfig& rig, const std::string& loop_name) {
  return schedule_of(find_loop(rig, loop_name));
}

control::JointLoopParams joint_loop_params(const config::RigConfig& rig) {
  const config::LoopConfig& joint = find_loop(rig, "joint");
  control::JointLoopParams params;
  params.command_timeout_s = joint.command_timeout_s;
  params.feedback_timeout_s = joint.feedback_timeout_s;
  return params;
}

control::VergenceParams vergence_params(const config::ExperimentConfig& experiment,
                                        const hal::HardwareInfo& hardware) {
  if (!hardware.stereo) throw std::runtime_error("the vergence task needs a stereo rig");
  const bool right_verges = experiment.vergence.verging_eye == hal::Eye::kRight;
  const hal::CameraInfo* verging = hardware.find_camera(
      right_verges ? hardware.stereo->right_camera : hardware.stereo->left_camera);
  if (verging == nullptr) throw std::runtime_error("the stereo pair names an unknown camera");
  control::VergenceParams params;
  params.verging_eye = experiment.vergence.verging_eye;
  params.focal_px = verging->intrinsics.focal_x_px;
  params.gain = experiment.vergence.gain;
  params.min_confidence = experiment.vergence.min_confidence;
  params.max_step_rad = experiment.vergence.max_step_rad;
  return params;
}

}  // namespace cambio::app
