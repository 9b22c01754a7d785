#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cambio/hal/joint_group.hpp"
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

struct GroupCommands {
  std::array<hal::JointCommand, kMaxJointsPerGroup> commands{};
  std::uint32_t count = 0;
};

struct GroupReadings {
  std::array<hal::JointState, kMaxJointsPerGroup> states{};
  std::int64_t stamp_ns = 0;
  std::uint32_t count = 0;
};

/// The channels between one joint group (joint loop thread) and the physics loop.
struct GroupLink {
  std::string name;
  std::vector<int> joints;  ///< Indices into World::joints(), in the group's order.
  hal::SeqlockChannel<GroupCommands> commands;
  hal::SeqlockChannel<GroupReadings> readings;
  std::uint64_t commands_seen = 0;  ///< Physics side: version of the last command block applied.
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

/// The sim's physics step as a loop: applies the joint groups' latest commands to the servo
/// models, drives the joints (kinematic ones set from the servo, the others by PD torque),
/// moves scripted objects, steps MuJoCo, then publishes encoder readings, touch readings and
/// the world snapshot. Runs at the rig's sim.physics_rate_hz. update() is real-time safe.
class PhysicsLoop final : public hal::Loop {
 public:
  /// Builds the servos (one per rig joint, seeded from `seed` and the joint's index).
  PhysicsLoop(World& world, std::uint64_t seed);

  const std::string& name() const override { return name_; }
  void activate() override;
  hal::Status update(const hal::LoopTick& tick) noexcept override;

  /// Set up before activate() (the backend calls these while making devices).
  GroupLink& add_group(const std::string& group_name, const std::vector<int>& joints);
  TouchLink& add_touch_sensor(const std::string& sensor_name, const std::vector<int>& bodies);

  /// Snapshots for the renderer and for ground truth (each a single-reader TripleBuffer).
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
  void publish(std::int64_t stamp_ns) noexcept;
  void set_kinematic_joints() noexcept;

  std::string name_ = "physics";
  World& world_;
  std::vector<ServoModel> servos_;
  std::vector<DriveGains> gains_;
  std::vector<std::unique_ptr<GroupLink>> groups_;
  std::vector<std::unique_ptr<TouchLink>> touches_;
  std::unique_ptr<hal::TripleBuffer<WorldSnapshot>> render_snapshots_;
  std::unique_ptr<hal::TripleBuffer<WorldSnapshot>> truth_snapshots_;
  std::atomic<std::uint64_t> steps_{0};
  std::atomic<bool> faulted_{false};
};

}  // namespace cambio::sim
