// The noisy servo model on its own: noise statistics, limits, dead time, rate limits, encoder.
#include "cambio/sim/servo_model.hpp"

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace cambio::sim {
namespace {

ServoParams params(double noise_std_rad) {
  ServoParams p;
  p.joint_name = "test";
  p.step_s = 0.001;
  p.min_position_rad = -1.0;
  p.max_position_rad = 1.0;
  p.max_velocity_rad_s = 2.0;
  p.max_acceleration_rad_s2 = 20.0;
  p.motion_noise_std_rad = noise_std_rad;
  p.velocity_window_steps = 10;
  return p;
}

TEST(ServoModelTest, MotionNoiseStandardDeviationIsWithinFivePercentOverTenThousandSteps) {
  for (const double configured : {1e-4, 5e-4, 2e-3}) {
    ServoModel servo(params(configured), 42, 0.0);
    double sum = 0.0, sum_sq = 0.0;
    int moving = 0;
    // 10,000 samples of motion (the sine's turning points, where the drive is briefly at rest,
    // do not count).
    for (int k = 0; moving < 10'000; ++k) {
      // A slow sine keeps the joint moving, well inside its limits.
      (void)servo.command({hal::CommandMode::kPosition, 0.5 * std::sin(k * 0.001 * 2.0)});
      servo.step();
      if (servo.state().profile_velocity_rad_s == 0.0) continue;
      const double error = servo.output_position_rad() - servo.state().profile_position_rad;
      sum += error;
      sum_sq += error * error;
      ++moving;
    }
    const double mean = sum / moving;
    const double std_dev = std::sqrt(sum_sq / moving - mean * mean);
    EXPECT_NEAR(std_dev, configured, 0.05 * configured) << "configured " << configured;
    EXPECT_NEAR(mean, 0.0, 4.0 * configured / std::sqrt(moving));
  }
}

TEST(ServoModelTest, AStoppedServoHoldsStill) {
  ServoModel servo(params(1e-3), 1, 0.0);
  (void)servo.command({hal::CommandMode::kPosition, 0.3});
  for (int k = 0; k < 2'000; ++k) servo.step();
  const double rest = servo.output_position_rad();
  EXPECT_NEAR(rest, 0.3, 5e-3);
  for (int k = 0; k < 1'000; ++k) {
    servo.step();
    ASSERT_EQ(servo.output_position_rad(), rest);
  }
}

TEST(ServoModelTest, LimitsAreNeverExceededAndOutOfRangeCommandsAreFlagged) {
  ServoParams p = params(5e-3);  // Large noise to push against the limits.
  p.backlash_rad = 0.01;
  ServoModel servo(p, 7, 0.9);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> target(-3.0, 3.0);
  int flagged = 0, beyond = 0;
  for (int k = 0; k < 10'000; ++k) {
    hal::JointCommand command{
        k % 2000 < 1000 ? hal::CommandMode::kPosition : hal::CommandMode::kVelocity, target(rng)};
    if (k % 50 == 0) {
      const bool out_of_range = command.mode == hal::CommandMode::kPosition
                                    ? std::abs(command.value) > 1.0
                                    : std::abs(command.value) > 2.0;
      beyond += out_of_range ? 1 : 0;
      const bool clamped = servo.command(command);
      EXPECT_EQ(clamped, out_of_range);
      flagged += clamped ? 1 : 0;
    }
    servo.step();
    ASSERT_GE(servo.output_position_rad(), p.min_position_rad) << "step " << k;
    ASSERT_LE(servo.output_position_rad(), p.max_position_rad) << "step " << k;
    ASSERT_LE(std::abs(servo.state().profile_velocity_rad_s), p.max_velocity_rad_s + 1e-9);
  }
  EXPECT_EQ(flagged, beyond);
  EXPECT_GT(flagged, 0);
  EXPECT_TRUE(servo.command({hal::CommandMode::kPosition, std::nan("")}));
}

TEST(ServoModelTest, DeadTimeDelaysTheFirstEffect) {
  ServoParams p = params(0.0);
  p.dead_time_s = 0.005;
  p.dead_time_steps = 5;
  ServoModel servo(p, 1, 0.0);
  (void)servo.command({hal::CommandMode::kPosition, 0.5});
  for (int k = 0; k < 5; ++k) {
    servo.step();
    EXPECT_EQ(servo.output_position_rad(), 0.0) << "moved after " << k + 1 << " steps";
  }
  servo.step();
  EXPECT_GT(servo.output_position_rad(), 0.0);
}

TEST(ServoModelTest, VelocityAndAccelerationLimitsShapeTheMotion) {
  ServoModel servo(params(0.0), 1, -1.0);
  (void)servo.command({hal::CommandMode::kPosition, 1.0});
  double previous_v = 0.0;
  double peak_v = 0.0;
  for (int k = 0; k < 3'000; ++k) {
    servo.step();
    const double v = servo.state().profile_velocity_rad_s;
    EXPECT_LE(std::abs(v - previous_v), 20.0 * 0.001 + 1e-9);
    peak_v = std::max(peak_v, v);
    previous_v = v;
  }
  EXPECT_NEAR(peak_v, 2.0, 1e-9);
  EXPECT_NEAR(servo.output_position_rad(), 1.0, 1e-9);
  // Velocity commands too: ramp at the acceleration limit, then hold the commanded speed.
  (void)servo.command({hal::CommandMode::kVelocity, -1.0});
  for (int k = 0; k < 30; ++k) servo.step();
  EXPECT_NEAR(servo.state().profile_velocity_rad_s, -0.6, 1e-9);
  for (int k = 0; k < 100; ++k) servo.step();
  EXPECT_NEAR(servo.state().profile_velocity_rad_s, -1.0, 1e-9);
}

TEST(ServoModelTest, EncoderQuantisesToItsResolution) {
  ServoParams p = params(0.0);
  p.encoder_counts_per_rev = 4096;
  ServoModel servo(p, 1, 0.0);
  const double count = 2 * std::numbers::pi / 4096.0;
  servo.observe(0.3);
  EXPECT_NEAR(std::remainder(servo.encoder_position_rad(), count), 0.0, 1e-12);
  EXPECT_NEAR(servo.encoder_position_rad(), 0.3, count / 2 + 1e-12);
  // Velocity from the difference of readings over the window.
  for (int k = 1; k <= 10; ++k) servo.observe(0.3 + 0.5 * k * 0.001);
  EXPECT_NEAR(servo.encoder_velocity_rad_s(), 0.5, 2 * count / 0.01);
}

TEST(ServoModelTest, BacklashLagsTheOutputOnReversal) {
  ServoParams p = params(0.0);
  p.backlash_rad = 0.02;
  ServoModel servo(p, 1, 0.0);
  (void)servo.command({hal::CommandMode::kPosition, 0.5});
  for (int k = 0; k < 2'000; ++k) servo.step();
  EXPECT_NEAR(servo.state().motor_position_rad - servo.output_position_rad(), 0.01, 1e-5);
  (void)servo.command({hal::CommandMode::kPosition, 0.2});
  for (int k = 0; k < 2'000; ++k) servo.step();
  EXPECT_NEAR(servo.state().motor_position_rad - servo.output_position_rad(), -0.01, 1e-5);
}

TEST(ServoModelTest, BrakeToStopRampsDownAtTheAccelerationLimitDropsQueuedTargetsAndHolds) {
  ServoParams p = params(1e-3);
  p.dead_time_s = 0.005;
  p.dead_time_steps = 5;
  ServoModel servo(p, 1, -1.0);
  (void)servo.command({hal::CommandMode::kPosition, 1.0});
  for (int k = 0; k < 300; ++k) servo.step();
  ASSERT_NEAR(servo.state().profile_velocity_rad_s, 2.0, 1e-9) << "cruising";
  (void)servo.command({hal::CommandMode::kPosition, 0.9});  // Queued behind the dead time.
  servo.brake_to_stop();
  double previous_v = servo.state().profile_velocity_rad_s;
  int steps_to_stop = 0;
  while (!servo.at_rest() && steps_to_stop < 1'000) {
    servo.step();
    const double v = servo.state().profile_velocity_rad_s;
    ASSERT_LE(std::abs(v - previous_v), p.max_acceleration_rad_s2 * p.step_s + 1e-9);
    ASSERT_GE(v, 0.0) << "brakes, never reverses";
    previous_v = v;
    ++steps_to_stop;
  }
  // 2 rad/s at 20 rad/s^2 stops in 0.1 s: 100 steps, from the first one (no dead time).
  EXPECT_EQ(steps_to_stop, 100);
  const double rest = servo.output_position_rad();
  for (int k = 0; k < 1'000; ++k) {
    servo.step();
    ASSERT_EQ(servo.output_position_rad(), rest) << "the queued target was dropped";
  }
}

TEST(ServoModelTest, HoldAtTakesTheMeasuredPositionAndForgetsOldTargets) {
  ServoParams p = params(1e-3);
  p.backlash_rad = 0.01;
  p.dead_time_s = 0.005;
  p.dead_time_steps = 5;
  ServoModel servo(p, 1, 0.0);
  (void)servo.command({hal::CommandMode::kPosition, 0.8});
  servo.step();
  servo.hold_at(0.25);
  for (int k = 0; k < 500; ++k) {
    servo.step();
    ASSERT_EQ(servo.output_position_rad(), 0.25) << "step " << k;
  }
  EXPECT_TRUE(servo.at_rest());
  // New targets are followed again, after the dead time.
  (void)servo.command({hal::CommandMode::kPosition, 0.5});
  for (int k = 0; k < 6; ++k) servo.step();
  EXPECT_EQ(servo.output_position_rad(), 0.25) << "inside the backlash band after the delay";
  for (int k = 0; k < 1'000; ++k) servo.step();
  EXPECT_NEAR(servo.output_position_rad(), 0.5 - 0.005, 5e-3);
  // Out of range: clamped to the limits.
  servo.hold_at(3.0);
  EXPECT_EQ(servo.output_position_rad(), p.max_position_rad);
}

TEST(ServoModelTest, SameSeedSameNoiseDifferentSeedDifferentNoise) {
  auto run = [](std::uint64_t seed) {
    ServoModel servo(params(1e-3), seed, 0.0);
    std::vector<double> trajectory;
    for (int k = 0; k < 500; ++k) {
      (void)servo.command({hal::CommandMode::kVelocity, 0.5});
      servo.step();
      trajectory.push_back(servo.output_position_rad());
    }
    return trajectory;
  };
  EXPECT_EQ(run(5), run(5));
  EXPECT_NE(run(5), run(6));
}

}  // namespace
}  // namespace cambio::sim
