#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cambio/canopen/can_joint_group.hpp"
#include "cambio/control/arm_reach_loop.hpp"
#include "cambio/control/command_tracking.hpp"
#include "cambio/control/gaze_loop.hpp"
#include "cambio/perception/ssm_server.hpp"
#include "cambio/ros2/perception_link.hpp"
#include "cambio/ros2/ros2_bridge.hpp"
#include "cambio/runtime/loop_statistics.hpp"
#include "cambio/sim/egl_context.hpp"

namespace cambio::app {

/// What one CAN joint group counted during the run (the socketcan backend's CanGroupCounters).
struct CanGroupReport {
  std::string group;
  canopen::CanGroupCounters counters;
  /// The joints that homed: at activate, then on request while the run went on.
  std::vector<canopen::HomingRecord> homing;
  std::string last_homing_error;  ///< Why the last homing on request failed; empty if none did.
};

/// What the experiment's behaviour did (MainJobResult::behaviour).
struct BehaviourReport {
  std::string name;
  std::vector<std::string> plugins;  ///< The libraries loaded, in order.
  std::uint64_t steps = 0;
  std::string status;  ///< Its last status line.
  bool failed = false;
  std::string error;  ///< Why it stopped, when it failed.
};

/// What a run produced, for the report and --out.
struct MainJobResult {
  std::vector<runtime::LoopStatistics> loops;
  bool realtime = false;
  std::uint64_t camera_frames = 0;
  std::uint64_t stereo_pairs = 0;
  std::uint64_t mismatched_stereo_pairs = 0;  ///< Refused by the SSM: eyes' stamps too far apart.
  /// Summed over the joint loops (one per group rate):
  std::uint64_t watchdog_cycles = 0;      ///< Joint loop held: targets went stale.
  std::uint64_t startup_hold_cycles = 0;  ///< Joint loop held: no targets sent yet.
  std::uint64_t fault_hold_cycles = 0;    ///< Joint loop held: fault latched or feedback stale.
  std::uint64_t fault_recoveries = 0;     ///< Fault resets asked by experiment.fault_recovery.
  bool fault_latched_at_end = false;
  /// Cameras that failed during the run (unplugged), one sentence each; they count as a fault
  /// latched at the end.
  std::vector<std::string> camera_faults;
  /// Each controller's tracking of its joints (gaze, arm or pose hold): frozen cycles, restarts,
  /// the largest command lead, a tracking fault.
  std::vector<control::TrackingReport> tracking;
  /// A controller latched a tracking fault: its joints stopped following, it held since.
  bool tracking_fault() const {
    for (const auto& report : tracking) {
      if (report.faulted) return true;
    }
    return false;
  }
  bool stopped_by_signal = false;
  double simulated_s = 0.0;
  double wall_s = 0.0;
  std::optional<perception::SsmSummary> perception;  ///< The newest, if perception ran.
  /// With perception on another host: what crossed the link, and its outages.
  std::optional<ros2::RobotPerceptionLinkCounts> perception_link;
  std::optional<control::GazeStatus> gaze;  ///< If the task was gaze: the last status.
  std::uint64_t gaze_rejected_commands = 0;
  std::uint64_t gaze_corrections = 0;
  std::uint64_t gaze_measurements = 0;
  /// Disparity measurements the vergence did not follow, by why (see control::GazeLoop).
  std::uint64_t gaze_held_jumps = 0;
  std::uint64_t gaze_occlusion_rejections = 0;
  std::uint64_t gaze_doubtful_departures = 0;
  std::uint64_t gaze_faint_steps = 0;
  std::uint64_t gaze_pursuit_region_frames = 0;
  std::uint64_t gaze_anchor_returns = 0;
  std::uint64_t gaze_reanchors = 0;
  std::uint64_t gaze_false_anchors = 0;
  /// The scripted commands' send times (s from the script's start; -1: not sent).
  std::vector<double> command_sent_s;
  std::int64_t script_start_ns = 0;  ///< The script's time 0 on the run's clock.
  /// If the run had an arm loop: its last status, and which sides it has ([0] left, [1] right).
  std::optional<control::ArmStatus> arms;
  std::array<bool, 2> arm_present{};
  std::vector<CanGroupReport> can_groups;    ///< One per socketcan group.
  std::optional<BehaviourReport> behaviour;  ///< If the experiment has one.
  /// What the sim's cameras rendered with; none when the run made no renderer.
  std::optional<sim::RendererDescription> renderer;
  /// What the ROS 2 bridge sent and took, if the run had one.
  std::optional<ros2::BridgeCounts> ros2;
};

}  // namespace cambio::app
