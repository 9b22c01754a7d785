#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "cambio/ros2/tf_tree.hpp"

namespace cambio::ros2 {

/// What the bridge publishes, and where.
struct BridgeSettings {
  /// The DDS domain (ROS_DOMAIN_ID); 0-232 keep RTPS's port formula within 16 bits.
  std::uint32_t domain_id = 0;
  /// /joint_states per second of wall time; 0 publishes none.
  double joint_states_rate_hz = 50.0;
  /// Also publish /clock (rosgraph_msgs/Clock) with each joint state's stamp: for simulated-time
  /// runs, so ROS tools with use_sim_time follow a run faster or slower than real time.
  bool publish_clock = false;
  /// Publish the rig's tree: /tf (each joint's link, with every joint state) and /tf_static (the
  /// cameras' optical frames, once, kept for late joiners).
  bool publish_tf = true;
  /// Added to the run's clock to make ROS time: 0 for simulated time, CLOCK_REALTIME minus
  /// CLOCK_MONOTONIC for a run on the wall clock.
  std::int64_t epoch_offset_ns = 0;
};

/// The newest believed state of every joint, in the order of the names the bridge was given.
struct JointStatesSample {
  std::int64_t stamp_ns = 0;  ///< On the run's clock.
  std::vector<double> position_rad;
  std::vector<double> velocity_rad_s;
  std::vector<double> effort_nm;
};

/// Fills `sample` (its vectors already sized to the joint count) with the newest state; false
/// while there is none yet. Called on the bridge's thread: it must read the loops' latest-value
/// channels, never wait for a loop.
using JointStatesSampler = std::function<bool(JointStatesSample& sample)>;

/// How much the bridge has sent since start().
struct BridgeCounts {
  std::uint64_t joint_states = 0;
  std::uint64_t clock = 0;
  std::uint64_t tf = 0;
  std::uint64_t write_errors = 0;
};

/// The run as a ROS 2 node on Cyclone DDS: /joint_states (sensor_msgs/JointState, reliable
/// keep-last 10), /tf (tf2_msgs/TFMessage, reliable keep-last 100), /tf_static (transient-local
/// keep-last 1) and, when asked, /clock (rosgraph_msgs/Clock), under the DDS names rmw_cyclonedds
/// gives them (topic `rt/joint_states`, type `sensor_msgs::msg::dds_::JointState_`).
/// It runs on a thread of its own, not real-time, that samples the loops' channels at its rate:
/// a loop never waits for the network. The DDS configuration is Cyclone's own (CYCLONEDDS_URI).
class Ros2Bridge {
 public:
  /// Creates the DDS participant and writers; throws std::runtime_error naming what Cyclone
  /// refused (a domain it cannot join, a bad CYCLONEDDS_URI) and std::invalid_argument for more
  /// joints than a message should carry or a rate outside [0, 1000] Hz.
  Ros2Bridge(const BridgeSettings& settings, std::vector<std::string> joint_names, TfTree tf_tree,
             JointStatesSampler sampler);
  ~Ros2Bridge();
  Ros2Bridge(const Ros2Bridge&) = delete;
  Ros2Bridge& operator=(const Ros2Bridge&) = delete;

  /// Publishes /tf_static and starts the publishing thread (once).
  void start();
  /// Publishes the newest state one last time and stops the thread; the writers stay, so a
  /// reliable reader still gets what was sent (they linger for it when destroyed).
  void stop();
  BridgeCounts counts() const;

 private:
  struct Dds;
  void publish_loop();
  void publish_newest();
  void publish_tf(std::int64_t stamp_ns);
  void publish_tf_static();

  BridgeSettings settings_;
  std::vector<std::string> joint_names_;
  TfTree tf_tree_;
  JointStatesSampler sampler_;
  JointStatesSample sample_;  // Preallocated; the bridge's thread only.
  std::int64_t last_published_stamp_ns_ = -1;
  std::unique_ptr<Dds> dds_;
  std::thread thread_;
  bool started_ = false;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;  // Guarded by mutex_.
  std::atomic<std::uint64_t> joint_states_sent_{0};
  std::atomic<std::uint64_t> clock_sent_{0};
  std::atomic<std::uint64_t> tf_sent_{0};
  std::atomic<std::uint64_t> write_errors_{0};
};

}  // namespace cambio::ros2
