#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/control/believed_joints.hpp"

namespace cambio::control {

/// What a controller reports of its joints' tracking after a run (MainJobResult, summary.json).
struct TrackingReport {
  std::string controller;
  std::uint64_t frozen_cycles = 0;  ///< Cycles it froze because its joints did not follow.
  std::uint64_t restarts = 0;       ///< Times it restarted from the measured pose.
  /// The largest |command - measured| seen while its joints followed, the joint and its limit.
  double peak_error_rad = 0.0;
  std::string peak_joint;
  double peak_joint_limit_rad = std::numeric_limits<double>::infinity();
  bool faulted = false;
  std::string fault;  ///< Why, when faulted.
};

/// A controller's guard against wind-up. The controllers integrate on the commanded pose (their
/// laws do not fight the drives' lag), so when the drives do not follow (a joint loop holding on a
/// fault or stale feedback, a drive disabled or homing) nothing would pull the command back: it
/// drifts from the robot, and after a recovery the joints rush to a stale target (ros2_control's
/// "command jump on re-activation"). Each cycle the controller asks step():
///  - kFrozen while a joint loop holds or one of its joints is not driven: it publishes its
///    command unchanged and integrates nothing (no servo, no profile time, no vergence);
///  - kRestart on the first cycle they follow again: restart() sets the command to the measured
///    pose, which it publishes unmoved; its motion resumes from there the next cycle. After a
///    brief hold (at most kBriefHoldCycles, every drive enabled throughout) it resumes instead
///    (kFollow): the joints are where the command had them going;
///  - kFollow otherwise: it steps, then check() bounds |command - measured| per joint: the first
///    joint beyond its max_error_rad latches a tracking fault (a drive that does not follow while
///    nothing says so: a slow or blocked drive, a brake left on);
///  - kFaulted once latched, to the end of the run: the controller holds where the joints were.
/// Construction allocates; everything else is real-time safe (no allocation, no locks) and runs on
/// the controller's thread.
class CommandTracking {
 public:
  enum class Step : std::uint8_t { kFollow, kFrozen, kRestart, kFaulted };

  struct Joint {
    std::string name;
    int rig = 0;    ///< In BelievedJoints' rig order.
    int index = 0;  ///< In the controller's own command and measurement spans.
    /// Beyond this |command - measured| is a fault; infinity: unbounded.
    double max_error_rad = std::numeric_limits<double>::infinity();
  };

  /// No joints: always kFollow (until given some by assignment).
  CommandTracking() = default;
  /// Throws std::invalid_argument for a limit that is not > 0 (NaN included) or a negative index.
  CommandTracking(std::string controller, std::vector<Joint> joints);

  /// From the believed joints just read (BelievedJoints::read this cycle).
  Step step(const BelievedJoints& believed) noexcept;
  /// Every guarded joint's command set to its measured position.
  void restart(std::span<double> q_command, std::span<const double> q_measured) noexcept;
  /// After a kFollow step: true when a bounded joint's command is beyond its limit of the
  /// measurement, which latches the fault (fault_message()).
  bool check(std::span<const double> q_command, std::span<const double> q_measured) noexcept;
  /// A joint whose lag is its task (a gripper squeezing what it holds) is left unbounded while
  /// `bounded` is false; `joint` indexes the constructor's list.
  void set_bounded(std::size_t joint, bool bounded) noexcept;

  bool faulted() const { return faulted_; }
  std::string_view fault_message() const { return std::string_view(message_.data()); }
  std::uint64_t frozen_cycles() const { return frozen_cycles_; }
  std::uint64_t restarts() const { return restarts_; }
  const std::vector<Joint>& joints() const { return joints_; }
  /// Not real-time safe (allocates): after the run.
  TrackingReport report() const;

 private:
  std::string controller_;
  std::vector<Joint> joints_;
  std::vector<std::uint8_t> bounded_;
  /// Holds this short with the drives enabled are late feedback, not a loss of the robot.
  static constexpr std::uint64_t kBriefHoldCycles = 5;
  bool frozen_ = false;
  bool drive_lost_ = false;  ///< A joint was not driven (disabled, faulted) during this freeze.
  std::uint64_t frozen_run_cycles_ = 0;
  bool faulted_ = false;
  std::uint64_t frozen_cycles_ = 0;
  std::uint64_t restarts_ = 0;
  double peak_error_rad_ = 0.0;
  int peak_joint_ = -1;
  std::array<char, 200> message_{};
};

}  // namespace cambio::control
