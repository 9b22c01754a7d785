#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "cambio/hal/camera.hpp"
#include "cambio/hal/stereo_frame.hpp"
#include "cambio/hal/triple_buffer.hpp"
#include "cambio/ros2/tf_tree.hpp"

namespace cambio::ros2 {

/// What the bridge publishes, and where.
struct BridgeSettings {
  /// The DDS domain (ROS_DOMAIN_ID); 0-232 keep RTPS's port formula within 16 bits.
  std::uint32_t domain_id = 0;
  /// /joint_states per second of wall time; 0 publishes none (nor /tf, nor /clock).
  double joint_states_rate_hz = 50.0;
  /// Also publish /clock (rosgraph_msgs/Clock) with each joint state's stamp: for simulated-time
  /// runs, so ROS tools with use_sim_time follow a run faster or slower than real time.
  bool publish_clock = false;
  /// Publish the rig's tree: /tf (each joint's link, with every joint state) and /tf_static (the
  /// cameras' optical frames, once, kept for late joiners).
  bool publish_tf = true;
  /// The stereo pair's newest images (and camera_info) per second of wall time; 0: none.
  double images_rate_hz = 0.0;
  /// /diagnostics per second of wall time (ROS's diagnostic_updater publishes at 1 Hz); 0: none.
  double diagnostics_rate_hz = 0.0;
  /// /cambio/gaze/fixation and /cambio/gaze/status per second of wall time; 0: none.
  double gaze_rate_hz = 0.0;
  /// The node's name in ROS 2's graph (`ros2 node list` shows /NAME): published on
  /// ros_discovery_info as rmw_cyclonedds does, with the participant's and endpoints' GIDs.
  std::string node_name = "cambio";
  /// Added to the run's clock to make ROS time: 0 for simulated time, CLOCK_REALTIME minus
  /// CLOCK_MONOTONIC for a run on the wall clock.
  std::int64_t epoch_offset_ns = 0;
};

/// The newest believed state of every joint, in the order of the bridge's joint names.
struct JointStatesSample {
  std::int64_t stamp_ns = 0;  ///< On the run's clock.
  std::vector<double> position_rad;
  std::vector<double> velocity_rad_s;
  std::vector<double> effort_nm;
};

/// Fills `sample` (its vectors already sized to the joint count) with the newest state; false
/// while there is none yet. Called on the bridge's thread: it must read the loops' latest-value
/// channels, never wait for a loop.
/// Called from more than one of the bridge's threads: it must keep no scratch state of its own.
using JointStatesSampler = std::function<bool(JointStatesSample& sample)>;

/// One component's state, as diagnostic_msgs/DiagnosticStatus says it.
struct DiagnosticEntry {
  enum class Level : std::uint8_t { kOk = 0, kWarn = 1, kError = 2, kStale = 3 };
  Level level = Level::kOk;
  std::string name;  ///< e.g. "cambio: drive neck_pan".
  std::string message;
  std::string hardware_id;
  std::vector<std::pair<std::string, std::string>> values;
};

/// Fills `entries` (cleared by the caller) with every component's state now and `stamp_ns` with
/// the run's clock; false while there is nothing to say yet. Called on the bridge's diagnostics
/// thread (it may allocate: that thread is not a loop's).
using DiagnosticsSampler =
    std::function<bool(std::int64_t& stamp_ns, std::vector<DiagnosticEntry>& entries)>;

/// The gaze as the robot believes it: where it fixates, and the gaze loop's state.
struct GazeSample {
  std::int64_t stamp_ns = 0;
  bool fixation_valid = false;
  std::array<double, 3> fixation_base_m{};  ///< The believed fixation point, frame "base".
  DiagnosticEntry status;                   ///< Action, disparity, confidence, vergence...
};
/// Fills `sample` with the newest gaze status; false while there is none. Bridge thread.
using GazeSampler = std::function<bool(GazeSample& sample)>;

/// Sends a look-at target (a point in "base", the world frame) to the gaze loop: returns "" when
/// it was sent, else why not. Called on the bridge's command thread.
using LookAtHandler = std::function<std::string(const Eigen::Vector3d& p_base_m)>;

/// Carries out one console line sent on /cambio/command (`saccade point 1 0.1 1.4`, `verge off`,
/// ...): returns "" when it was carried out, else why not. Called on the bridge's command thread.
using RemoteCommandHandler = std::function<std::string(const std::string& line)>;

/// A trajectory_msgs/JointTrajectory as received, its arrays' sizes checked by the bridge (a
/// position per joint at every point; a velocity per joint at every point, or none at all).
/// Accelerations and efforts are not used (the trajectory is interpolated from positions and
/// velocities), nor is header.stamp (a trajectory starts when the loop takes it).
struct TrajectoryMessage {
  std::vector<std::string> joint_names;
  std::vector<double> time_from_start_s;  ///< Per point.
  std::vector<double> positions_rad;      ///< Point-major: [point * joints + joint].
  std::vector<double> velocities_rad_s;   ///< The same layout, or empty: positions only.
};
/// Carries out a joint trajectory: returns "" when it was sent to the loop, else why not. Called
/// on the bridge's command thread.
using TrajectoryHandler = std::function<std::string(const TrajectoryMessage& trajectory)>;

/// Where the bridge's data comes from.
struct BridgeSources {
  std::vector<std::string> joint_names;  ///< The joint states' order.
  TfTree tf_tree;
  JointStatesSampler joint_states;
  /// The stereo pairs the camera loop publishes (the bridge is this channel's one reader), and
  /// the two cameras (left, right): each published as /<camera>/image_raw and camera_info. Null:
  /// no images.
  hal::TripleBuffer<hal::StereoFrame>* stereo_images = nullptr;
  std::array<hal::CameraInfo, 2> stereo_cameras;
  /// Subscribes /cambio/look_at (geometry_msgs/PointStamped, in any frame of the tf tree); each
  /// refusal is published on /cambio/refusals (std_msgs/String) and logged. Null: no commands.
  LookAtHandler look_at;
  /// Subscribes /cambio/joint_trajectory (trajectory_msgs/JointTrajectory) with the look-at
  /// target; null: not subscribed. Messages with more points or joints than the loops take
  /// (trajectory_max_points, trajectory_max_joints) are refused before they are copied.
  TrajectoryHandler joint_trajectory;
  std::size_t trajectory_max_points = 0;
  std::size_t trajectory_max_joints = 0;
  /// Each loop, drive, CAN group and the gaze as /diagnostics; null: none.
  DiagnosticsSampler diagnostics;
  /// The gaze as /cambio/gaze/fixation (geometry_msgs/PointStamped in base) and
  /// /cambio/gaze/status (diagnostic_msgs/DiagnosticStatus); null: none.
  GazeSampler gaze;
  /// The robot as a URDF (make_urdf), published once on /robot_description (std_msgs/String,
  /// transient-local, as robot_state_publisher does); empty: not published.
  std::string robot_description;
};

/// How much the bridge has sent since start().
struct BridgeCounts {
  std::uint64_t joint_states = 0;
  std::uint64_t clock = 0;
  std::uint64_t tf = 0;
  std::uint64_t images = 0;
  std::uint64_t camera_infos = 0;
  std::uint64_t diagnostics = 0;
  std::uint64_t gaze = 0;
  /// Commands taken. A flood beyond the readers' keep-last 10 is dropped by DDS before the
  /// bridge sees it (Cyclone reports no loss for keep-last): the sender knows how many it sent.
  std::uint64_t commands_received = 0;
  std::uint64_t commands_refused = 0;
  std::uint64_t write_errors = 0;
};

/// The run as a ROS 2 node on Cyclone DDS, under the DDS names rmw_cyclonedds gives ROS topics
/// and types (topic `rt/joint_states`, type `sensor_msgs::msg::dds_::JointState_`):
///   /joint_states  sensor_msgs/JointState   reliable keep-last 10
///   /tf            tf2_msgs/TFMessage       reliable keep-last 100
///   /tf_static     tf2_msgs/TFMessage       reliable transient-local keep-last 1
///   /clock         rosgraph_msgs/Clock      reliable keep-last 10 (when asked)
///   /<camera>/image_raw, /<camera>/camera_info   sensor_msgs/Image, CameraInfo, best-effort
///                                                 keep-last 5 (ROS's sensor-data QoS)
///   /robot_description  std_msgs/String      reliable transient-local keep-last 1
///   /cambio/refusals  std_msgs/String        reliable keep-last 10 (with commands)
///   /diagnostics      diagnostic_msgs/DiagnosticArray   reliable keep-last 10 (when asked)
///   /cambio/gaze/fixation  geometry_msgs/PointStamped   reliable keep-last 10 (when asked)
///   /cambio/gaze/status    diagnostic_msgs/DiagnosticStatus  reliable keep-last 10
///   ros_discovery_info     rmw_dds_common/ParticipantEntitiesInfo (no "rt/": ROS 2's own
///                          graph topic) reliable transient-local keep-last 1: this node,
///                          its readers and writers, so ROS 2 tools list it (Iron and later:
///                          the 16-byte GID)
/// and subscribes, when given a look-at handler:
///   /cambio/look_at   geometry_msgs/PointStamped   reliable keep-last 10 (a flood beyond that
///                                                   is dropped by DDS, never queued)
///   /cambio/command   std_msgs/String              reliable keep-last 10: a console line
///   /cambio/joint_trajectory  trajectory_msgs/JointTrajectory  reliable keep-last 10 (when
///                                                   given a trajectory handler)
/// Threads of its own, not real-time, sample the loops' channels at their rates and wait for
/// commands: a loop never waits for the network. The DDS configuration is Cyclone's own
/// (CYCLONEDDS_URI).
class Ros2Bridge {
 public:
  /// Creates the DDS participant and writers; throws std::runtime_error naming what Cyclone
  /// refused (a domain it cannot join, a bad CYCLONEDDS_URI) and std::invalid_argument for more
  /// joints than a message should carry, a rate outside [0, 1000] Hz, or a tf joint without a
  /// position.
  Ros2Bridge(const BridgeSettings& settings, BridgeSources sources);
  ~Ros2Bridge();
  Ros2Bridge(const Ros2Bridge&) = delete;
  Ros2Bridge& operator=(const Ros2Bridge&) = delete;

  /// The console lines of /cambio/command go to `handler` (before start(); a run that takes
  /// commands, i.e. has a look-at handler, subscribes the topic whether or not one is set, and
  /// refuses its lines without one).
  void set_command_handler(RemoteCommandHandler handler) { command_handler_ = std::move(handler); }

  /// Publishes /tf_static and /robot_description and starts the publishing threads (once).
  void start();
  /// Publishes the newest state one last time and stops the threads; the writers stay, so a
  /// reliable reader still gets what was sent (they linger for it when destroyed).
  void stop();
  BridgeCounts counts() const;

 private:
  struct Dds;
  void run_every(double rate_hz, void (Ros2Bridge::*publish)());
  void publish_joint_states();
  void publish_tf(std::int64_t stamp_ns);
  void publish_tf_static();
  /// The node and its endpoints on ros_discovery_info (once, when made: they never change).
  void publish_discovery_info();
  void publish_images();
  void publish_diagnostics();
  void publish_gaze();
  void publish_image(std::size_t eye, const hal::Image& image);
  void serve_commands();
  void handle_look_at(const void* point_stamped);
  void refuse(const std::string& reason);
  void handle_command(const void* string_message);
  void handle_trajectory(const void* joint_trajectory);
  /// Writes `message`; counts it in `sent` (if given) or in the write errors.
  bool write(std::int32_t writer, const void* message, std::atomic<std::uint64_t>* sent);

  BridgeSettings settings_;
  BridgeSources sources_;
  RemoteCommandHandler command_handler_;
  std::array<std::string, 2> optical_frames_;  // The stereo cameras' frame ids.
  JointStatesSample sample_;                   // Preallocated; the joint-state thread's only.
  JointStatesSample command_sample_;           // Likewise, the command thread's.
  std::int64_t last_published_stamp_ns_ = -1;
  std::unique_ptr<Dds> dds_;
  std::vector<std::thread> threads_;
  bool started_ = false;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;  // Guarded by mutex_.
  std::atomic<std::uint64_t> joint_states_sent_{0};
  std::atomic<std::uint64_t> clock_sent_{0};
  std::atomic<std::uint64_t> tf_sent_{0};
  std::atomic<std::uint64_t> images_sent_{0};
  std::atomic<std::uint64_t> camera_infos_sent_{0};
  std::atomic<std::uint64_t> diagnostics_sent_{0};
  std::atomic<std::uint64_t> gaze_sent_{0};
  std::atomic<std::uint64_t> commands_received_{0};
  std::atomic<std::uint64_t> commands_refused_{0};
  std::atomic<std::uint64_t> write_errors_{0};
};

}  // namespace cambio::ros2
