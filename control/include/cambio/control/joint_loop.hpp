#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "cambio/control/joint_frames.hpp"
#include "cambio/control/rig_hold.hpp"
#include "cambio/hal/joint_group.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"

namespace cambio::control {

struct JointLoopParams {
  /// Targets older than this are stale: the joints hold until fresh targets arrive.
  double command_timeout_s = 0.1;
  /// A joint reading older than this is stale: no joint moves until readings are fresh again.
  double feedback_timeout_s = 0.02;
  /// activate() asks every drive to enable (deactivate() always quick-stops them).
  bool enable_on_activate = true;
  /// The loop's name in statistics: "joint" for the rig-wide loop, "joint.<group>" for a loop
  /// of groups that run at a rate of their own.
  std::string name = "joint";
  /// Where this loop's joints sit in the target frame, which then holds `target_count` joints
  /// (the whole rig's, when groups run in several loops). Empty: the frame is this loop's joints
  /// in order.
  std::vector<int> target_indices;
  int target_count = 0;
  /// Shared with the rig's other joint loops, so that all hold while one does; null when this
  /// loop drives the whole rig.
  RigHold* rig_hold = nullptr;
  /// Recovery from a latched fault without restarting: after holding this long, the loop asks
  /// every drive for a fault reset and then enable (at the measured positions), at most
  /// `max_fault_recoveries` times per run. 0 recoveries (the default): a fault holds to the end.
  double fault_recovery_delay_s = 0.5;
  int max_fault_recoveries = 0;
  /// After a fault reset, every joint that must home and lost its reference (its drive
  /// rebooted) homes again before it is enabled. Off: such a joint stays disabled until homed on
  /// request (request_home).
  bool home_after_reboot = false;
};

/// The fast loop next to the hardware (1 kHz by default). Each cycle, in this order:
///  1. read() every group: per-joint states, stamps, drive states, error codes;
///  2. safety: a joint whose reading is older than feedback_timeout_s is flagged kJointStale;
///     kJointFault and kJointCommLost are latched until a fault reset; while anything is latched
///     or stale the loop holds every joint (the last target sent, velocity 0) and never sends
///     motion;
///  3. per joint: position limits (clamped; NaN holds), the velocity limit as a ramp (a position
///     target moves at most max_velocity * period per cycle), and a watchdog (targets older than
///     command_timeout_s hold the joints);
///     a joint that is not operation enabled is sent its measured position, and the first
///     target after it becomes enabled is exactly its measured position (enabling never jumps);
///  4. write() every group, then sync() every group (a CAN group sends SYNC here).
/// The returned status is the most severe of the cycle's (hal::worst), never the last one seen.
/// Joint order is the concatenation of the groups' joint lists. The state frame it publishes
/// holds this loop's joints; the target frame may be the whole rig's (params.target_indices).
class JointLoop final : public hal::Loop {
 public:
  JointLoop(std::vector<hal::JointGroup*> groups, hal::SeqlockChannel<JointTargetFrame>& targets,
            hal::SeqlockChannel<JointStateFrame>& states, JointLoopParams params);

  const std::string& name() const override { return name_; }
  /// Checks the joint count fits kMaxJoints; sizes the scratch buffers. Throws on a bad setup.
  void configure() override;
  /// Reads once so the first targets hold the current pose; requests enable if configured.
  void activate() override;
  hal::Status update(const hal::LoopTick& tick) noexcept override;
  /// Quick-stops every drive.
  void deactivate() noexcept override;

  /// Asks every joint for a lifecycle transition, applied at the start of the next cycle.
  /// kFaultReset also clears the loop's latched bits once no drive reports a fault; an enable
  /// asked together with it is sent only then (a drive takes one request at a time).
  /// Thread-safe, wait-free (any thread: the decision layer, a console, a test).
  void request(hal::DriveRequest request) noexcept;
  /// Asks joint `joint` (this loop's order) to home again (hal::DriveRequest::kHome), at the
  /// start of the next cycle. Returns false for a joint outside the loop. Thread-safe,
  /// wait-free. Whether the joint homes at all is its group's to say: one that does not refuses.
  bool request_home(int joint) noexcept;
  /// request_home() calls the joint's group refused (it does not home), and the last such joint
  /// (this loop's order; -1: none).
  std::uint64_t homes_refused() const { return homes_refused_.load(std::memory_order_relaxed); }
  int last_refused_home() const { return last_refused_home_.load(std::memory_order_relaxed); }

  int joint_count() const { return joint_count_; }
  /// Cycles in which the watchdog held the joints because targets went stale (or came malformed)
  /// after the control loop had sent some.
  std::uint64_t stale_cycles() const { return stale_cycles_.load(std::memory_order_relaxed); }
  /// Cycles held at start-up, before the control loop sent its first targets: the joint loop
  /// publishes the states the controller reads, so at least its first cycle comes before them.
  std::uint64_t awaiting_targets_cycles() const {
    return awaiting_targets_cycles_.load(std::memory_order_relaxed);
  }
  /// Fault resets the loop asked by itself (JointLoopParams::max_fault_recoveries).
  std::uint64_t fault_recoveries() const {
    return fault_recoveries_.load(std::memory_order_relaxed);
  }
  /// Cycles held because a fault or lost joint was latched, or feedback was stale.
  std::uint64_t fault_hold_cycles() const {
    return fault_hold_cycles_.load(std::memory_order_relaxed);
  }
  std::uint64_t feedback_stale_cycles() const {
    return feedback_stale_cycles_.load(std::memory_order_relaxed);
  }

 private:
  void apply_requests(std::uint32_t pending) noexcept;
  hal::Status read_groups(std::int64_t now_ns) noexcept;
  void forward(hal::DriveRequest request) noexcept;
  void forward_home(std::uint64_t joints) noexcept;
  /// Asks a fault reset and enable when a latch has lasted fault_recovery_delay_s (and
  /// recoveries remain).
  void recover_if_asked(bool fault_latched, std::int64_t now_ns) noexcept;

  std::string name_;
  std::vector<hal::JointGroup*> groups_;
  hal::SeqlockChannel<JointTargetFrame>& targets_;
  hal::SeqlockChannel<JointStateFrame>& states_;
  JointLoopParams params_;
  int joint_count_ = 0;
  std::vector<hal::JointLimits> limits_;
  std::vector<hal::JointState> state_scratch_;
  std::vector<hal::JointCommand> command_scratch_;
  std::vector<double> last_position_target_;  // What was sent last cycle, for the ramp and hold.
  std::vector<std::uint32_t> latched_bits_;   // kJointLatchingBits seen since the last reset.
  std::vector<std::uint8_t> was_enabled_;
  JointTargetFrame targets_frame_{};  // The last clean copy of the targets.
  JointStateFrame state_frame_{};
  int rig_hold_slot_ = 0;
  std::atomic<std::uint32_t> pending_requests_{0};  // Bit per hal::DriveRequest.
  std::atomic<std::uint64_t> pending_homes_{0};     // Bit per joint (request_home).
  std::atomic<std::uint64_t> homes_refused_{0};
  std::atomic<int> last_refused_home_{-1};
  bool reset_requested_ = false;     // Clear the latches once the drives report no fault.
  bool enable_after_reset_ = false;  // Then ask them to enable.
  std::atomic<std::uint64_t> stale_cycles_{0};
  std::atomic<std::uint64_t> awaiting_targets_cycles_{0};
  std::atomic<std::uint64_t> fault_hold_cycles_{0};
  std::atomic<std::uint64_t> fault_recoveries_{0};
  std::int64_t fault_latched_since_ns_ = -1;  // When the current latch began; -1: none.
  std::atomic<std::uint64_t> feedback_stale_cycles_{0};
};

}  // namespace cambio::control
