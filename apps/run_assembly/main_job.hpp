#pragma once

#include <array>
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cambio/behaviour/behaviour_loop.hpp"
#include "cambio/behaviour/plugin_libraries.hpp"
#include "cambio/canopen/can_joint_group.hpp"
#include "cambio/config/experiment_config.hpp"
#include "cambio/control/arm_reach_loop.hpp"
#include "cambio/control/command_script.hpp"
#include "cambio/control/gaze_loop.hpp"
#include "cambio/control/joint_loop.hpp"
#include "cambio/control/pose_hold_loop.hpp"
#include "cambio/control/rig_hold.hpp"
#include "cambio/hal/backend_factory.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/hal/joint_state_tap.hpp"
#include "cambio/perception/camera_loop.hpp"
#include "cambio/perception/ssm_server.hpp"
#include "cambio/runtime/executor.hpp"
#include "cambio/runtime/lockstep_executor.hpp"
#include "cambio/runtime/loop_statistics.hpp"
#include "cambio/sim/egl_context.hpp"
#include "cambio/sim/ground_truth.hpp"
#include "main_job_result.hpp"
#include "robot_actions.hpp"
#include "run_trace.hpp"

namespace cambio::ros2 {
class Ros2Bridge;
class RobotPerceptionLink;
}  // namespace cambio::ros2

namespace cambio::app {

/// The experiment's behaviour could not be set up: a plugin that does not load, an unknown
/// name, a bad parameter. A problem of the experiment's input, not of a device.
class BehaviourSetupError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What a run is for: an experiment (the defaults) or the console.
struct MainJobOptions {
  /// Send the experiment's timed gaze commands (false: someone else, the console, commands the
  /// gaze loop).
  bool send_script = true;
  /// Record the evaluation trace (believed vs true at the control rate) for metrics and plots.
  bool record_trace = true;
};

/// The main job. Construction builds the run and configures it (throws on any problem):
///  1. the executor, which owns the run's one clock: realtime on CLOCK_MONOTONIC when any device
///     is on a backend registered as paced by the wall clock (hal::BackendTraits: real hardware)
///     or the experiment asks for it, lockstep otherwise;
///  2. the backends through the factory, given that clock and the HAL's hardware description;
///     their devices; a backend that models the whole robot (follows_other_backends(): the sim)
///     follows every group another backend drives, so its cameras see what the drives did;
///  3. Backend::configure() of every backend, then what each offers (Backend::offer: ground
///     truth, counters, renderers), asked for by type, never by backend name;
///  4. the loops, wired through latest-value channels:
///       camera loop -> (stereo pairs) -> perception loop (SSM) -> control loop -> joint loop(s)
///     plus the backends' own loops (the sim's physics), and with a `behaviour:` the behaviour
///     loop (its plugins loaded, the built-ins registered; it is the gaze commands' writer in
///     place of the script); with `ros2:`, the bridge to ROS 2 (its own thread, reading the
///     joint loops' channels). Groups at the rig-wide joint rate share
///     the loop "joint"; groups with a rate_hz of their own run in a loop per rate
///     (control::plan_joint_loops), all reading the rig-wide targets and holding together.
/// run() activates the backends, runs the executor (loops: configure, activate, update...,
/// deactivate), and deactivates the backends whatever happens (a signal included).
class MainJob {
 public:
  MainJob(const config::ExperimentConfig& experiment, const hal::BackendFactory& factory,
          MainJobOptions options = {});
  ~MainJob();

  /// Runs for `duration_s` (negative: the experiment's duration) or until `stop`;
  /// `progress(done_s, wall_s)` is called about every 0.1 s of run time, by either executor.
  MainJobResult run(const std::atomic<bool>& stop,
                    const std::function<void(double, double)>& progress, double duration_s = -1.0);

  /// Runs under the caller's control, on the lockstep executor only (throws std::logic_error on
  /// the realtime one): asks `next_stop_ns(now_ns)` for the clock time to run to, runs every
  /// loop up to it, and asks again, until it returns a negative time or `stop` is set. While it
  /// decides, no loop runs: it may read and write the loops' channels on this thread.
  MainJobResult run_stepped(const std::atomic<bool>& stop,
                            const std::function<std::int64_t(std::int64_t)>& next_stop_ns);

  /// The gaze loop's command channel (one writer: the script, or whoever send_script=false let
  /// command it). Null unless the task is gaze.
  hal::SeqlockChannel<control::GazeCommand>* gaze_commands() {
    return gaze_loop_ != nullptr ? &gaze_commands_ : nullptr;
  }
  const control::GazeLoop* gaze_loop() const { return gaze_loop_; }
  /// Features the decision layer asks of the SSM besides the gaze's (one writer); null unless
  /// the task is gaze.
  hal::SeqlockChannel<perception::FeatureRequest>* feature_requests() {
    return gaze_loop_ != nullptr ? &feature_requests_ : nullptr;
  }
  /// Asks `joint` to home again, or with an empty name every joint that must home and lost its
  /// reference (hal::DriveRequest::kHome), from the next joint-loop cycle. Returns false for a
  /// name that is no rig joint. A joint that does not home is refused by its group:
  /// homes_refused() counts those, last_refused_home() names the last.
  bool request_home(const std::string& joint);
  std::uint64_t homes_refused() const;
  std::string last_refused_home() const;
  /// Whether the run takes commands from ROS 2 (`ros2: {commands: true}` on the gaze task):
  /// then `handler` carries out the console lines of /cambio/command (set before run()).
  bool set_remote_command_handler(std::function<std::string(const std::string&)> handler);
  /// A reader of the joint loops' published states (the believed joints), rig order.
  control::BelievedJoints make_believed_joints() const;
  /// The rig's joints in rig order (the command frames' order).
  const std::vector<std::string>& joint_order() const { return joint_order_; }
  /// The control loops' period (the gaze and arm loops take one command per cycle).
  std::int64_t control_period_ns() const;
  const hal::HardwareInfo& hardware() const { return hardware_; }
  /// The simulator's ground truth; null when the rig has no sim backend.
  sim::GroundTruth* ground_truth();
  /// The SSM loop; null when the rig has no stereo pair or the SSM runs on another host
  /// (`ros2.split: perception_remote`).
  perception::SsmServer* perception() { return perception_loop_.get(); }
  /// The SSM's results and the requests for it, wherever it runs: the SsmServer's channels, or
  /// the perception link's. Null when the rig has no stereo pair.
  const hal::SeqlockChannel<perception::SsmSummary>* ssm_summaries() const;
  hal::SeqlockChannel<perception::SsmRequest>* ssm_requests();
  /// The stereo pair's images for one more reader beside the SSM (the console's `capture`), or
  /// null when the rig has no pair or another reader (the ROS 2 bridge's images) has them. Call
  /// before run().
  hal::TripleBuffer<hal::StereoFrame>* claim_observed_stereo_frames();

  /// The newest frame of each camera (rig order), for --out, after run(); sequence 0 if none
  /// arrived. A foveated sim eye (config::SimFoveationConfig) is rendered whole instead, at the
  /// end of the run: images for people are full frames.
  std::vector<hal::Image> last_frames();
  const std::vector<hal::CameraInfo>& cameras() const { return hardware_.cameras; }
  /// What the run recorded at the control rate with the simulator's ground truth (trace.csv,
  /// metrics, plots); null when the rig has no sim backend or no stereo pair. Read after run().
  const Trace* trace() const { return trace_ ? &trace_->trace() : nullptr; }
  /// Where a console or behaviour sends the arms their commands (ArmCommand: a new sequence is a
  /// new command). Read only when the run has an arm loop (arm_status() not null).
  hal::SeqlockChannel<control::ArmCommand>& arm_commands() { return arm_commands_; }
  /// The robot's actions on this run's command channels (what behaviours and the console use);
  /// null unless the task is gaze.
  RobotActions* actions() { return actions_.get(); }
  /// The arms' status each control cycle; null when the run has no arm loop (not task gaze, or
  /// no arm group with a touch sensor on its gripper).
  const hal::SeqlockChannel<control::ArmStatus>* arm_status() const {
    return arm_loop_ ? &arm_loop_->status() : nullptr;
  }
  /// The head's joints in the trace (pan/tilt of neck and eyes), for plots.
  std::vector<std::string> head_joint_names() const;
  /// Paced by the wall clock (realtime executor) rather than simulated time.
  bool realtime() const { return realtime_; }
  /// What the sim's renderer renders with, if the run has one (the sim made it for a camera);
  /// asking never makes one.
  std::optional<sim::RendererDescription> renderer() const;

 private:
  // The backends and their devices (main_job_devices.cpp).
  void build_backends(const hal::BackendFactory& factory);
  hal::Backend& backend_for(const hal::BackendFactory& factory, const hal::BackendContext& context,
                            const std::string& name, const std::string& requested_by);
  void follow_driven_groups();
  void follow_groups_of_other_backends(const std::string& follower_name, hal::Backend& follower);
  void make_touch_sensors(const hal::BackendFactory& factory, const hal::BackendContext& context);
  // The loops, in the order the executor is given them (main_job_loops.cpp, main_job_control.cpp).
  void build_loops();
  void build_joint_loops();
  perception::SsmConfig build_camera_and_perception_loops();
  void build_control_loop(const control::JointTargetFrame& pose);
  void build_gaze_loop(const control::JointTargetFrame& pose);
  void build_arm_loop(const control::JointTargetFrame& pose,
                      std::vector<control::BelievedJoints::Source> sources);
  void add_backend_loops();
  void build_trace();
  void build_actions();
  void build_behaviour(const perception::SsmConfig& ssm);
  void build_ros2_bridge();  // main_job_ros2.cpp
  void build_perception_link();
  /// Throws std::runtime_error (a device fault) when no perception host answers in time.
  void wait_for_perception_host();
  void collect(MainJobResult& result);
  int joint_index(const std::string& joint_name) const;
  std::size_t camera_index(const std::string& camera_name) const;  // Rig order; throws if none.

  config::ExperimentConfig experiment_;
  MainJobOptions options_;
  hal::HardwareInfo hardware_;
  // The executor owns the clock the backends hold: it is destroyed last.
  std::unique_ptr<runtime::Executor> executor_;
  runtime::LockstepExecutor* lockstep_ = nullptr;  // executor_, when the run is lockstep.
  bool realtime_ = false;
  std::map<std::string, std::unique_ptr<hal::Backend>, std::less<>> backends_;
  hal::BackendOffers offers_;  // What the backends offer besides devices, after configure().
  std::vector<std::unique_ptr<hal::JointGroup>> groups_;
  std::vector<std::unique_ptr<hal::JointStateTap>> taps_;  // Groups another backend follows.
  std::vector<hal::JointGroup*> driven_groups_;            // What the joint loop drives, rig order.
  std::vector<std::unique_ptr<hal::Camera>> cameras_;
  std::vector<std::string> joint_order_;  // Rig order: the groups' joint lists concatenated.

  /// A joint loop and the states it publishes (its own joints, in its groups' order).
  struct JointLoopSlot {
    std::unique_ptr<hal::SeqlockChannel<control::JointStateFrame>> states;
    std::vector<int> rig_indices;  // Where its joints sit in rig order.
    std::unique_ptr<control::JointLoop> loop;
  };

  hal::SeqlockChannel<control::JointTargetFrame> targets_;  // Rig order, every joint.
  control::RigHold rig_hold_;                               // Outlives the joint loops.
  std::vector<JointLoopSlot> joint_loops_;
  std::unique_ptr<hal::Loop> control_loop_;
  control::GazeLoop* gaze_loop_ = nullptr;      // control_loop_ when the task is gaze.
  control::PoseHoldLoop* pose_hold_ = nullptr;  // control_loop_ otherwise.
  hal::SeqlockChannel<control::GazeCommand> gaze_commands_;
  // Joint trajectories (from ROS 2) for the gaze loop's head joints and the arm loop's.
  hal::SeqlockChannel<control::JointTrajectory> head_trajectories_;
  hal::SeqlockChannel<control::JointTrajectory> arm_trajectories_;
  hal::SeqlockChannel<perception::FeatureRequest> feature_requests_;
  std::unique_ptr<control::CommandScript> script_;  // The experiment's timed commands.
  // The arms: their touch sensors by side ([0] left, [1] right), the loop, its commands.
  std::array<std::unique_ptr<hal::TouchSensor>, 2> touch_sensors_;
  std::array<std::string, 2> arm_groups_;
  hal::SeqlockChannel<control::ArmCommand> arm_commands_;
  std::unique_ptr<control::ArmReachLoop> arm_loop_;
  std::unique_ptr<TraceRecorder> trace_;  // Evaluation: believed vs true, per cycle.
  std::unique_ptr<perception::CameraLoop> camera_loop_;
  std::unique_ptr<perception::SsmServer> perception_loop_;
  // With `ros2.split: perception_remote` the SSM runs on another host: its request and result
  // channels are these, carried by the link (main_job_ros2.cpp).
  bool perception_remote_ = false;
  hal::SeqlockChannel<perception::SsmSummary> remote_summaries_;
  hal::SeqlockChannel<perception::SsmRequest> remote_requests_;
  std::unique_ptr<ros2::RobotPerceptionLink> perception_link_;

  // The behaviour. The plugins are declared first so that they are closed last: the registry's
  // factories and the behaviour a plugin made hold its code.
  std::unique_ptr<behaviour::PluginLibraries> plugins_;
  std::unique_ptr<behaviour::BehaviourRegistry> registry_;
  std::unique_ptr<behaviour::Behaviour> behaviour_;
  std::unique_ptr<RobotActions> actions_;  // On this run's channels; null unless task gaze.
  std::unique_ptr<behaviour::BehaviourLoop> behaviour_loop_;
  // With `ros2:`, the run as a ROS 2 node; publishing while run() or run_stepped() runs.
  std::unique_ptr<ros2::Ros2Bridge> ros2_bridge_;
  bool observed_stereo_claimed_ = false;  // The camera loop's observed pairs have their reader.
};

}  // namespace cambio::app
