#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "cambio/config/rig_config.hpp"
#include "cambio/hal/joint_group.hpp"

namespace cambio::sim {

/// What does not change during a run (MuJoCo's mjModel / Drake's System split): limits, the
/// noise and delay settings, the step. Built at configure time.
struct ServoParams {
  std::string joint_name;
  double step_s = 0.001;  ///< The physics step the servo advances by.
  double min_position_rad = 0.0;
  double max_position_rad = 0.0;
  double max_velocity_rad_s = 0.0;
  double max_acceleration_rad_s2 = 0.0;
  double dead_time_s = 0.0;
  double motion_noise_std_rad = 0.0;
  double backlash_rad = 0.0;
  std::int64_t encoder_counts_per_rev = 0;  ///< 0 = ideal encoder.
  int dead_time_steps = 0;                  ///< round(dead_time_s / step_s).
  int velocity_window_steps = 10;           ///< Encoder velocity: difference over this many steps.

  static ServoParams from_joint(const config::JointConfig& joint, double step_s);
};

/// What changes every step.
struct ServoState {
  hal::JointCommand pending{};  ///< Latest command received, entering the delay line next step.
  std::vector<hal::JointCommand> pipeline;  ///< Dead-time delay line (ring), sized at configure.
  std::size_t pipeline_head = 0;
  hal::JointCommand active{};  ///< The command the servo currently executes (after the delay).
  double profile_position_rad = 0.0;  ///< Velocity/acceleration-limited motion, noise-free.
  double profile_velocity_rad_s = 0.0;
  double motion_error_rad = 0.0;     ///< Gaussian error of the executed motion.
  double motor_position_rad = 0.0;   ///< Profile + error: where the drive puts its side.
  double output_position_rad = 0.0;  ///< After backlash: the joint's commanded true position.
  double output_velocity_rad_s = 0.0;
  std::vector<double> encoder_history;  ///< Last quantised readings (ring), for velocity.
  std::size_t encoder_head = 0;
  std::uint64_t steps = 0;
  std::mt19937_64 rng;
};

/// The sim's servo: a drive that executes position or velocity commands after a dead time,
/// within velocity and acceleration limits, with a Gaussian motion error (the paper's
/// "controlled Gaussian errors"), optional backlash, and an encoder that quantises what it
/// reports.
///
/// Motion error model: while the drive moves (the profile velocity is not zero), every step it
/// lands at profile + e with e ~ N(0, motion_noise_std_rad) drawn afresh; when it comes to rest,
/// it stays where its last step put it (a stopped servo does not jitter). So the error of the
/// executed motion has exactly the configured standard deviation and never accumulates.
///
/// Limits: positions outside [min, max] are clamped before they enter the delay line (the
/// caller learns it from command()'s return), the profile decelerates to stop at a limit, and
/// the output is clamped, so no position beyond a limit is ever executed.
class ServoModel {
 public:
  /// Allocates the delay line and encoder history. `seed` makes the noise reproducible.
  ServoModel(ServoParams params, std::uint64_t seed, double initial_position_rad);

  const ServoParams& params() const { return params_; }
  const ServoState& state() const { return state_; }

  /// Queues a command (it takes effect after the dead time). Returns true if it had to be
  /// clamped to a limit (position beyond [min, max], or velocity beyond +-max). Real-time safe.
  bool command(const hal::JointCommand& command) noexcept;

  /// Advances one step. Real-time safe.
  void step() noexcept;

  /// The drive stops following commands (quick stop, fault reaction, or not enabled): queued
  /// commands are dropped and the profile decelerates at max_acceleration_rad_s2 to a standstill,
  /// where it holds (a drive's quick-stop ramp). Real-time safe.
  void brake_to_stop() noexcept;
  /// The drive is enabled where the joint is: `measured_position_rad` (clamped to the limits)
  /// becomes the profile's position at rest and the target, queued commands are dropped, so
  /// enabling never moves the joint towards an old target. Real-time safe.
  void hold_at(double measured_position_rad) noexcept;
  /// True when the profile stands still (a braking drive has stopped).
  bool at_rest() const { return state_.profile_velocity_rad_s == 0.0; }
  /// Effort feed-forward of the command being executed (after the dead time), N m.
  double effort_feedforward_nm() const { return state_.active.effort_feedforward_nm; }

  /// The position the servo drives the joint to (truth for kinematic joints; the reference of
  /// the physics PD for the others).
  double output_position_rad() const { return state_.output_position_rad; }
  double output_velocity_rad_s() const { return state_.output_velocity_rad_s; }

  /// What the encoder reports for a true joint position, and the velocity from the difference of
  /// readings over velocity_window_steps. Call once per step with the true position (after
  /// step() and physics). Real-time safe.
  void observe(double true_position_rad) noexcept;
  double encoder_position_rad() const;
  double encoder_velocity_rad_s() const;

  /// Quantises a position to the encoder's resolution (identity for an ideal encoder).
  double quantise(double position_rad) const noexcept;

 private:
  /// Replaces everything queued (pending, the delay line, the active command) by `command`.
  void replace_queue(const hal::JointCommand& command) noexcept;
  void advance_position_profile(double target_rad) noexcept;
  void advance_velocity_profile(double velocity_rad_s) noexcept;

  ServoParams params_;
  ServoState state_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace cambio::sim
