#include "cambio/sim/servo_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace cambio::sim {

ServoParams ServoParams::from_joint(const config::JointConfig& joint, double step_s) {
  ServoParams params;
  params.joint_name = joint.name;
  params.step_s = step_s;
  params.min_position_rad = joint.min_position_rad;
  params.max_position_rad = joint.max_position_rad;
  params.max_velocity_rad_s = joint.max_velocity_rad_s;
  params.max_acceleration_rad_s2 = joint.max_acceleration_rad_s2;
  params.dead_time_s = joint.servo.dead_time_s;
  params.motion_noise_std_rad = joint.servo.motion_noise_std_rad;
  params.backlash_rad = joint.servo.backlash_rad;
  params.encoder_counts_per_rev = joint.servo.encoder_counts_per_rev;
  params.dead_time_steps = static_cast<int>(std::lround(joint.servo.dead_time_s / step_s));
  // A 10 ms window: 0.01 rad/s resolution with a 65536-count encoder, little lag.
  params.velocity_window_steps = std::max(1, static_cast<int>(std::lround(0.01 / step_s)));
  return params;
}

ServoModel::ServoModel(ServoParams params, std::uint64_t seed, double initial_position_rad)
    : params_(std::move(params)) {
  const double start =
      std::clamp(initial_position_rad, params_.min_position_rad, params_.max_position_rad);
  const hal::JointCommand hold{hal::CommandMode::kPosition, start, 0.0, 0.0};
  state_.pending = hold;
  state_.active = hold;
  state_.pipeline.assign(static_cast<std::size_t>(params_.dead_time_steps) + 1, hold);
  state_.profile_position_rad = start;
  state_.motor_position_rad = start;
  state_.output_position_rad = start;
  state_.encoder_history.assign(static_cast<std::size_t>(params_.velocity_window_steps) + 1,
                                quantise(start));
  state_.rng.seed(seed);
}

bool ServoModel::command(const hal::JointCommand& command) noexcept {
  hal::JointCommand accepted = command;
  const bool clamped = hal::clamp_command(accepted, params_.min_position_rad,
                                          params_.max_position_rad, params_.max_velocity_rad_s);
  state_.pending = accepted;
  return clamped;
}

void ServoModel::advance_position_profile(double target_rad) noexcept {
  const double dt = params_.step_s;
  const double a = params_.max_acceleration_rad_s2;
  const double error = target_rad - state_.profile_position_rad;
  // Fastest approach that can still stop at the target in discrete steps: from v = n a dt the
  // drive covers a dt^2 n (n + 1) / 2 before it stands still, so n = sqrt(1/4 + 2|e|/(a dt^2))
  // - 1/2. Capped by the velocity limit and by what one step can cover.
  const double n = std::sqrt(0.25 + 2.0 * std::abs(error) / (a * dt * dt)) - 0.5;
  double desired = std::min({params_.max_velocity_rad_s, n * a * dt, std::abs(error) / dt});
  desired = std::copysign(desired, error);
  const double v = std::clamp(desired, state_.profile_velocity_rad_s - a * dt,
                              state_.profile_velocity_rad_s + a * dt);
  state_.profile_velocity_rad_s = v;
  state_.profile_position_rad += v * dt;
  // The last step lands within a dt^2 / 8 of the target (fractional n): settle on it; the
  // next step's velocity is then 0, within one step's deceleration.
  if (std::abs(target_rad - state_.profile_position_rad) <= 0.125 * a * dt * dt + 1e-12 &&
      std::abs(v) <= a * dt) {
    state_.profile_position_rad = target_rad;
  }
}

void ServoModel::advance_velocity_profile(double velocity_rad_s) noexcept {
  const double dt = params_.step_s;
  const double a = params_.max_acceleration_rad_s2;
  const double x = state_.profile_position_rad;
  // Brake early enough to stop at a position limit rather than at the hard clamp.
  double target = velocity_rad_s;
  if (target > 0.0)
    target = std::min(target, std::sqrt(2.0 * a * std::max(0.0, params_.max_position_rad - x)));
  if (target < 0.0)
    target = std::max(target, -std::sqrt(2.0 * a * std::max(0.0, x - params_.min_position_rad)));
  const double v = std::clamp(target, state_.profile_velocity_rad_s - a * dt,
                              state_.profile_velocity_rad_s + a * dt);
  state_.profile_velocity_rad_s = v;
  state_.profile_position_rad += v * dt;
}

void ServoModel::step() noexcept {
  auto& s = state_;
  // Dead time: the command read now entered the delay line dead_time_steps steps ago.
  s.pipeline[s.pipeline_head] = s.pending;
  s.pipeline_head = (s.pipeline_head + 1) % s.pipeline.size();
  s.active = s.pipeline[s.pipeline_head];

  if (s.active.mode == hal::CommandMode::kPosition) {
    advance_position_profile(s.active.value);
  } else {
    advance_velocity_profile(s.active.value);
  }
  if (s.profile_position_rad > params_.max_position_rad) {
    s.profile_position_rad = params_.max_position_rad;
    s.profile_velocity_rad_s = std::min(0.0, s.profile_velocity_rad_s);
  } else if (s.profile_position_rad < params_.min_position_rad) {
    s.profile_position_rad = params_.min_position_rad;
    s.profile_velocity_rad_s = std::max(0.0, s.profile_velocity_rad_s);
  }

  // Motion error: drawn afresh on every step of a motion, held when the drive is at rest.
  if (s.profile_velocity_rad_s != 0.0 && params_.motion_noise_std_rad > 0.0) {
    s.motion_error_rad = params_.motion_noise_std_rad * normal_(s.rng);
  }
  s.motor_position_rad = std::clamp(s.profile_position_rad + s.motion_error_rad,
                                    params_.min_position_rad, params_.max_position_rad);

  // Backlash: the output follows the motor only once the dead band is taken up.
  const double previous_output = s.output_position_rad;
  const double half_band = 0.5 * params_.backlash_rad;
  if (s.motor_position_rad - s.output_position_rad > half_band) {
    s.output_position_rad = s.motor_position_rad - half_band;
  } else if (s.motor_position_rad - s.output_position_rad < -half_band) {
    s.output_position_rad = s.motor_position_rad + half_band;
  }
  s.output_position_rad =
      std::clamp(s.output_position_rad, params_.min_position_rad, params_.max_position_rad);
  s.output_velocity_rad_s = (s.output_position_rad - previous_output) / params_.step_s;
  ++s.steps;
}

void ServoModel::replace_queue(const hal::JointCommand& command) noexcept {
  state_.pending = command;
  state_.active = command;
  std::fill(state_.pipeline.begin(), state_.pipeline.end(), command);
}

void ServoModel::brake_to_stop() noexcept {
  // A velocity target of 0 is the velocity profile's ramp down at the acceleration limit; it
  // then stays at rest (no motion error is drawn while at rest).
  replace_queue({hal::CommandMode::kVelocity, 0.0, 0.0, 0.0});
}

void ServoModel::hold_at(double measured_position_rad) noexcept {
  auto& s = state_;
  const double q =
      std::clamp(measured_position_rad, params_.min_position_rad, params_.max_position_rad);
  // Motor and output both at the measured position: the backlash band is centred and the motion
  // error starts from zero, so the output does not move on the next step.
  s.profile_position_rad = q;
  s.profile_velocity_rad_s = 0.0;
  s.motion_error_rad = 0.0;
  s.motor_position_rad = q;
  s.output_position_rad = q;
  s.output_velocity_rad_s = 0.0;
  replace_queue({hal::CommandMode::kPosition, q, 0.0, 0.0});
}

void ServoModel::observe(double true_position_rad) noexcept {
  auto& s = state_;
  s.encoder_head = (s.encoder_head + 1) % s.encoder_history.size();
  s.encoder_history[s.encoder_head] = quantise(true_position_rad);
}

double ServoModel::encoder_position_rad() const {
  return state_.encoder_history[state_.encoder_head];
}

double ServoModel::encoder_velocity_rad_s() const {
  const auto& s = state_;
  const std::size_t size = s.encoder_history.size();
  const std::size_t oldest = (s.encoder_head + 1) % size;
  return (s.encoder_history[s.encoder_head] - s.encoder_history[oldest]) /
         (static_cast<double>(size - 1) * params_.step_s);
}

double ServoModel::quantise(double position_rad) const noexcept {
  if (params_.encoder_counts_per_rev <= 0) return position_rad;
  const double count_rad =
      2 * std::numbers::pi / static_cast<double>(params_.encoder_counts_per_rev);
  return std::round(position_rad / count_rad) * count_rad;
}

}  // namespace cambio::sim
