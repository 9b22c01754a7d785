#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cambio/hal/clock.hpp"
#include "cambio/hal/drive_state.hpp"
#include "cambio/hal/joint_group.hpp"
#include "cambio/hal/joint_state_tap.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/hal/touch_sensor.hpp"
#include "cambio/hal/triple_buffer.hpp"
#include "cambio/sim/servo_model.hpp"
#include "cambio/sim/world.hpp"
#include "cambio/sim/world_snapshot.hpp"

namespace cambio::sim {

/// Most joints one sim group carries (fixed so commands and readings cross threads through a
/// SeqlockChannel without allocation).
inline constexpr std::size_t kMaxJointsPerGroup = 16;

/// The emergency error code a sim drive latches when it loses its master (CiA 301: "life guard
/// error or heartbeat error").
inline constexpr std::uint16_t kCommLossErrorCode = 0x8130;

struct GroupCommands {
  std::array<hal::JointCommand, kMaxJointsPerGroup> commands{};
  std::uint32_t count = 0;
};

struct GroupReadings {
  std::array<hal::JointState, kMaxJointsPerGroup> states{};
  std::int64_t stamp_ns = 0;  ///< The newest of the joints' stamps.
  std::uint32_t count = 0;
};

/// The channels between one joint group (joint loop thread) and the physics loop.
struct GroupLink {
  std::string name;
  std::vector<int> joints;  ///< Indices into World::joints(), in the group's order.
  hal::SeqlockChannel<GroupCommands> commands;
  hal::SeqlockChannel<GroupReadings> readings;
  /// Lifecycle requests, one word per joint: (count << 8) | DriveRequest. Each request bumps the
  /// count, so the physics loop sees every new request, a repeated one too.
  std::array<std::atomic<std::uint32_t>, kMaxJointsPerGroup> requests{};

  // Physics side only.
  std::uint64_t commands_seen = 0;  ///< Version of the last command block taken.
  std::array<std::uint32_t, kMaxJointsPerGroup> requests_seen{};
};

/// A group another backend drives, whose joints the world follows.
struct FollowLink {
  std::string name;
  std::vector<int> joints;  ///< Indices into World::joints(), in the leader's order.
  const hal::JointStateSource* leader = nullptr;
  std::vector<hal::JointState> latest;  ///< Sized at setup: the leader's newest readings.
};

struct TouchLink {
  std::string name;
  std::vector<char> end_effector_body;  ///< Per MuJoCo body: 1 if part of the end effector.
  hal::SeqlockChannel<hal::TouchReading> reading;
};

/// Gains of the position servo that drives a physics joint (PD on the servo model's reference
/// plus gravity feed-forward, as a real drive's current loop would see it).
struct DriveGains {
  double kp_nm_rad = 0.0;
  double kd_nm_s_rad = 0.0;
};

/// The sim's physics step as a loop: walks each joint's CiA 402 drive state towards its last
/// request, applies the joint groups' latest commands to the servo models of enabled drives,
/// drives the joints (kinematic ones set from the servo or the followed leader, the others by
/// PD torque), moves scripted objects, steps MuJoCo, then publishes encoder readings, touch
/// readings and the world snapshot. Runs at the rig's sim.physics_rate_hz. update() is real-time
/// safe.
///
/// Drives (one per rig joint): kNotReadyToSwitchOn until activate(), then kSwitchOnDisabled.
/// Requests walk hal::next_drive_state() one transition per step. Only an operation-enabled
/// drive executes commands; it is enabled holding the measured position, and commands written
/// before that are dropped, never executed later. A drive that leaves operation enabled (quick
/// stop, fault reaction, disable) while moving brakes at the joint's acceleration limit, then
/// holds where it stopped; one at rest holds its measured position. Holding is the simple and
/// safe choice for every non-enabled state: a head joint stays put, an arm is held by its PD with
/// gravity compensated (as a drive with its holding brake engaged; pressed against something, it
/// stops pushing). A fault reaction ends in kFault once the servo is at rest. Effort
/// feed-forward is added to a physics joint's torque; velocity feed-forward is ignored (the
/// servo's profile makes its own).
class PhysicsLoop final : public hal::Loop {
 public:
  /// Builds the servos (one per rig joint, seeded from `seed` and the joint's index). `clock` is
  /// the run's clock, for readings published outside a step.
  PhysicsLoop(World& world, hal::Clock& clock, std::uint64_t seed);

  const std::string& name() const override { return name_; }
  /// Boots the drives (kSwitchOnDisabled) and publishes the current state at the clock's time.
  /// Idempotent.
  void activate() override;
  hal::Status update(const hal::LoopTick& tick) noexcept override;
  /// Quick stops and disables every drive at once (the loop no longer steps, so there is no
  /// ramp to wait for): faulted drives stay faulted, every other one is kSwitchOnDisabled.
  /// Call it from the physics thread or once the loop stopped. Idempotent.
  void deactivate() noexcept override;

  /// Set up before activate() (the backend calls these while making devices); they throw
  /// std::logic_error once the loop is active.
  GroupLink& add_group(const std::string& group_name, const std::vector<int>& joints);
  TouchLink& add_touch_sensor(const std::string& sensor_name, const std::vector<int>& bodies);
  /// The world's `joints` follow the positions `leader` reports (in that order) from now on.
  void add_follower(const std::string& group_name, const std::vector<int>& joints,
                    const hal::JointStateSource& leader);

  /// Fault injection, for tests of the layers above. Each takes effect at the next step; any
  /// thread; real-time safe. `joint` indexes World::joints().
  /// A fault with an emergency error code (not 0): fault reaction, then kFault.
  void inject_fault(int joint, std::uint16_t emcy_error_code) noexcept;
  /// The drive loses its master: its reading freezes and carries kJointCommLost until a fault
  /// reset, and the drive runs its fault reaction (error kCommLossErrorCode).
  void inject_comm_loss(int joint) noexcept;
  /// The reading stops updating (its stamp with it) while the drive runs on.
  void freeze_feedback(int joint, bool frozen) noexcept;

  /// Snapshots for the cameras and for ground truth (each a single-reader TripleBuffer).
  hal::TripleBuffer<WorldSnapshot>& render_snapshots() { return *render_snapshots_; }
  hal::TripleBuffer<WorldSnapshot>& truth_snapshots() { return *truth_snapshots_; }

  const std::vector<ServoModel>& servos() const { return servos_; }
  const std::vector<DriveGains>& gains() const { return gains_; }
  std::uint64_t steps() const { return steps_.load(std::memory_order_relaxed); }
  /// True once MuJoCo reported an error or a diverging state; the loop then returns kFault.
  bool faulted() const { return faulted_.load(std::memory_order_relaxed); }

  /// Takes one step outside any executor (tests, benchmarks). Real-time safe.
  hal::Status step_once(std::int64_t stamp_ns) noexcept;

 private:
  /// What one rig joint's drive is doing. Physics thread only.
  struct Drive {
    hal::DriveState state = hal::DriveState::kNotReadyToSwitchOn;
    /// The last request, until a fault clears it (a fault latches until a new reset).
    hal::DriveRequest goal = hal::DriveRequest::kDisable;
    std::uint16_t error_code = 0;
    bool comm_lost = false;
    bool feedback_frozen = false;
    bool followed = false;
    double follow_position_rad = 0.0;
    double follow_velocity_rad_s = 0.0;
    hal::JointState reading;  ///< The last reading published (kept while frozen or lost).
  };
  /// Injected events, written by any thread, taken by the physics step.
  struct DriveEvents {
    std::atomic<std::uint32_t> fault{0};  ///< kFaultPending | error code, or 0.
    std::atomic<bool> comm_loss{false};
    std::atomic<bool> freeze{false};
  };
  static constexpr std::uint32_t kFaultPending = 1u << 16;

  void take_requests() noexcept;
  void take_commands() noexcept;
  void take_leaders() noexcept;
  void advance_drive(std::size_t joint) noexcept;
  void enter(std::size_t joint, hal::DriveState state) noexcept;
  void raise_fault(std::size_t joint, std::uint16_t error_code) noexcept;
  void publish(std::int64_t stamp_ns) noexcept;
  void publish_group(GroupLink& group, std::int64_t stamp_ns) noexcept;
  void set_kinematic_joints() noexcept;
  double reference_position_rad(std::size_t joint) const noexcept;
  double reference_velocity_rad_s(std::size_t joint) const noexcept;
  void require_inactive(const char* what) const;

  std::string name_ = "physics";
  World& world_;
  hal::Clock& clock_;
  std::vector<ServoModel> servos_;
  std::vector<DriveGains> gains_;
  std::vector<Drive> drives_;
  std::vector<DriveEvents> events_;
  std::vector<std::unique_ptr<GroupLink>> groups_;
  std::vector<std::unique_ptr<FollowLink>> followers_;
  std::vector<std::unique_ptr<TouchLink>> touches_;
  std::unique_ptr<hal::TripleBuffer<WorldSnapshot>> render_snapshots_;
  std::unique_ptr<hal::TripleBuffer<WorldSnapshot>> truth_snapshots_;
  std::atomic<std::uint64_t> steps_{0};
  std::atomic<bool> faulted_{false};
  bool active_ = false;
};

}  // namespace cambio::sim
