#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cambio/behaviour/behaviour.hpp"
#include "cambio/control/believed_joints.hpp"
#include "cambio/control/kinematics.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/hal/triple_buffer.hpp"
#include "cambio/perception/sensory_servo.hpp"

namespace cambio::behaviour {

/// What the behaviour loop reads. Channels must outlive the loop.
struct BehaviourLoopSources {
  const hal::SeqlockChannel<perception::SsmSummary>* ssm = nullptr;
  /// The SSM's full frames, asked for at configure() (the SSM makes them when it is configured:
  /// add this loop after it); this loop becomes their one reader. Empty, or returning null:
  /// Observation::ssm_frame stays null.
  std::function<hal::TripleBuffer<perception::SsmFrame>*()> ssm_frames;
  const hal::SeqlockChannel<control::GazeStatus>* gaze = nullptr;
  const hal::SeqlockChannel<control::ArmStatus>* arms = nullptr;  ///< Null on a head rig.
  /// The SSM's map names, in map order (perception::feature_map_specs of its operators).
  std::vector<std::string> feature_map_names;
};

/// Runs a user's behaviour (the paper's Decision Making Module) at its own rate: each cycle it
/// builds an Observation from the channels and calls Behaviour::start() (first cycle) or step()
/// with the Actions it was given. Not real-time: the behaviour may allocate and take its time,
/// so update() allocates (allocates_in_update() is true) and the loop must never run at a
/// real-time priority.
///
/// A behaviour that throws is stopped: the loop asks actions.hold() once (the robot keeps
/// still where it is), reports the error as this loop's fault, never calls the behaviour again,
/// and failed() / error() say so for the run's report and exit status; the run goes on.
class BehaviourLoop final : public hal::Loop {
 public:
  /// Throws std::invalid_argument when the hardware has no stereo pair or the dominant camera
  /// is not in the kinematic tree, std::invalid_argument for missing SSM or gaze channels.
  BehaviourLoop(std::string name, const hal::HardwareInfo& hardware, hal::Eye dominant_eye,
                BehaviourLoopSources sources, control::BelievedJoints believed,
                Behaviour& behaviour, Actions& actions);

  const std::string& name() const override { return name_; }
  void configure() override;
  void activate() override;
  hal::Status update(const hal::LoopTick& tick) noexcept override;
  bool allocates_in_update() const override { return true; }

  /// The behaviour threw; error() says what (and in which call).
  bool failed() const { return failed_; }
  const std::string& error() const { return error_; }
  /// Steps run (start() included). Read after the executor stopped.
  std::uint64_t steps() const { return steps_; }
  /// The behaviour's last status line (refreshed every step).
  const std::string& status() const { return status_; }

 private:
  void observe(const hal::LoopTick& tick);

  std::string name_;
  hal::Eye dominant_eye_;
  BehaviourLoopSources sources_;
  hal::TripleBuffer<perception::SsmFrame>* ssm_frames_ = nullptr;
  control::BelievedJoints believed_;
  Behaviour& behaviour_;
  Actions& actions_;
  control::Kinematics kinematics_;
  int dominant_camera_frame_ = -1;
  hal::CameraInfo dominant_camera_;
  std::vector<std::string> joint_names_;  // Rig order.
  std::vector<double> q_rig_rad_;
  perception::SsmSummary summary_{};
  control::GazeStatus gaze_{};
  control::ArmStatus arms_{};
  Observation observation_;
  bool started_ = false;
  std::int64_t start_ns_ = 0;
  bool failed_ = false;
  std::string error_;
  std::string status_;
  std::uint64_t steps_ = 0;
};

}  // namespace cambio::behaviour
