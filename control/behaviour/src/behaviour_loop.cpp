#include "cambio/behaviour/behaviour_loop.hpp"

#include <stdexcept>

namespace cambio::behaviour {

BehaviourLoop::BehaviourLoop(std::string name, const hal::HardwareInfo& hardware,
                             hal::Eye dominant_eye, BehaviourLoopSources sources,
                             control::BelievedJoints believed, Behaviour& behaviour,
                             Actions& actions)
    : name_(std::move(name)),
      dominant_eye_(dominant_eye),
      sources_(std::move(sources)),
      believed_(std::move(believed)),
      behaviour_(behaviour),
      actions_(actions),
      kinematics_(hardware) {
  if (sources_.ssm == nullptr || sources_.gaze == nullptr) {
    throw std::invalid_argument("behaviour loop: needs the SSM's summaries and the gaze status");
  }
  if (!hardware.stereo) throw std::invalid_argument("behaviour loop: the rig has no stereo pair");
  const std::string& camera = dominant_eye == hal::Eye::kLeft ? hardware.stereo->left_camera
                                                              : hardware.stereo->right_camera;
  const hal::CameraInfo* info = hardware.find_camera(camera);
  if (info == nullptr) {
    throw std::invalid_argument("behaviour loop: no camera '" + camera + "' in the rig");
  }
  dominant_camera_ = *info;
  dominant_camera_frame_ = kinematics_.frame_index(camera);
  for (const int tree : kinematics_.rig_to_tree()) {
    joint_names_.push_back(kinematics_.joint_name(tree));
  }
  q_rig_rad_.assign(joint_names_.size(), 0.0);
  if (believed_.rig_joint_count() != static_cast<int>(joint_names_.size())) {
    throw std::invalid_argument("behaviour loop: the believed joints are not the rig's");
  }
}

void BehaviourLoop::configure() {
  ssm_frames_ = sources_.ssm_frames ? sources_.ssm_frames() : nullptr;
}

void BehaviourLoop::activate() {
  started_ = false;
  observation_ = Observation{};
}

void BehaviourLoop::observe(const hal::LoopTick& tick) {
  Observation& o = observation_;
  o.now_ns = tick.now_ns;
  o.run_time_s = static_cast<double>(tick.now_ns - start_ns_) * 1e-9;
  sources_.ssm->read(summary_);
  o.ssm = summary_.sequence > 0 ? &summary_ : nullptr;
  if (ssm_frames_ != nullptr) {
    ssm_frames_->acquire();
    const perception::SsmFrame& frame = ssm_frames_->front();
    o.ssm_frame = frame.summary.sequence > 0 ? &frame : nullptr;
  }
  sources_.gaze->read(gaze_);
  o.gaze = sources_.gaze->version() > 0 ? &gaze_ : nullptr;
  if (sources_.arms != nullptr) {
    sources_.arms->read(arms_);
    o.arms = sources_.arms->version() > 0 ? &arms_ : nullptr;
  }
  (void)believed_.read(q_rig_rad_);
  o.q_believed_rig_rad = q_rig_rad_;
  o.joint_names = joint_names_;
  o.feature_map_names = sources_.feature_map_names;
  o.dominant_eye = dominant_eye_;
  o.dominant_camera = &dominant_camera_;
  // A non-finite reading leaves the previous pose (update_rig_order rejects it).
  (void)kinematics_.update_rig_order(q_rig_rad_);
  o.X_W_dominant_camera = kinematics_.X_WF(dominant_camera_frame_);
}

hal::Status BehaviourLoop::update(const hal::LoopTick& tick) noexcept {
  if (failed_) return hal::Status::kOk;
  const char* call = started_ ? "step()" : "start()";
  try {
    if (!started_) start_ns_ = tick.now_ns;
    observe(tick);
    if (!started_) {
      started_ = true;
      behaviour_.start(observation_, actions_);
    } else {
      behaviour_.step(observation_, actions_);
    }
    ++steps_;
    status_ = behaviour_.status();
    return hal::Status::kOk;
  } catch (const std::exception& error) {
    error_ = std::string("the behaviour's ") + call + " threw: " + error.what();
  } catch (...) {
    error_ = std::string("the behaviour's ") + call + " threw an unknown exception";
  }
  failed_ = true;
  try {
    // Keep the robot still where it is; the run goes on without the behaviour.
    const ActionResult held = actions_.hold();
    if (!held.sent) error_ += " (and hold was not sent: " + held.message + ")";
    status_ = "stopped: " + error_;
  } catch (...) {
    error_ += " (and hold threw)";
  }
  return report_fault(error_);
}

}  // namespace cambio::behaviour
