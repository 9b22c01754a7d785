#include "cambio/canopen/drive_parameters.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>

#include "cambio/canopen/cia402.hpp"

namespace cambio::canopen {

namespace {

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

std::int64_t checked_counts(double counts, const std::string& what) {
  if (!std::isfinite(counts) || std::abs(counts) > 2147483647.0) {
    throw std::invalid_argument(what + " is " + number(counts) +
                                " counts, beyond what a drive's INTEGER32 holds (2147483647); "
                                "check gear_ratio and encoder_counts_per_rev");
  }
  return std::llround(counts);
}

}  // namespace

InterpolationPeriod interpolation_period(double period_s) {
  if (!(period_s >= 1e-6 && period_s <= 255.0)) {
    throw std::invalid_argument("interpolation period " + std::to_string(period_s) +
                                " s is outside what 0x60C2 holds (1 us .. 255 s)");
  }
  InterpolationPeriod closest{};
  double closest_error = INFINITY;
  for (int index = 0; index >= -6; --index) {
    const double value = period_s / std::pow(10.0, index);
    const double rounded = std::round(value);
    if (rounded < 1.0 || rounded > 255.0) continue;
    const double error = std::abs(rounded - value) * std::pow(10.0, index);
    if (error <= 1e-9 * period_s) {
      return {static_cast<std::uint8_t>(rounded), static_cast<std::int8_t>(index)};
    }
    if (error < closest_error) {
      closest_error = error;
      closest = {static_cast<std::uint8_t>(rounded), static_cast<std::int8_t>(index)};
    }
  }
  return closest;
}

void check_drive_units(const hal::JointInfo& joint, const JointDriveInfo& drive) {
  const std::string name = "joint '" + joint.name + "'";
  if (drive.encoder_counts_per_rev <= 0 || !std::isfinite(drive.gear_ratio) ||
      drive.gear_ratio == 0.0) {
    throw std::invalid_argument(name + ": encoder_counts_per_rev must be > 0 and gear_ratio " +
                                "finite and non-zero");
  }
  const auto units = cia402::Units::from(drive.gear_ratio, drive.encoder_counts_per_rev);
  const double counts_per_turn = std::abs(units.counts_per_rad) * 2.0 * std::numbers::pi;
  if (!(counts_per_turn >= kMinCountsPerJointTurn)) {
    throw std::invalid_argument(
        name + ": gear_ratio " + number(drive.gear_ratio) + " x encoder_counts_per_rev " +
        std::to_string(drive.encoder_counts_per_rev) + " is " + number(counts_per_turn) +
        " counts per joint turn; expected at least " + number(kMinCountsPerJointTurn) +
        " (a count of at most a degree)");
  }
  const hal::JointLimits& limits = joint.limits;
  checked_counts(limits.min_position_rad * units.counts_per_rad, name + " min position");
  checked_counts(limits.max_position_rad * units.counts_per_rad, name + " max position");
  checked_counts(limits.max_velocity_rad_s * units.counts_per_rad, name + " max velocity");
  checked_counts(drive.following_error_window_rad * units.counts_per_rad,
                 name + " following error window");
}

std::vector<ObjectWrite> drive_parameter_writes(const hal::JointInfo& joint,
                                                const JointDriveInfo& drive,
                                                const hal::JointGroupInfo& group,
                                                const CanGroupSettings& settings, double rate_hz) {
  check_drive_units(joint, drive);
  const std::string name = "joint '" + joint.name + "'";
  if (!(rate_hz > 0.0)) {
    throw std::invalid_argument("joint group '" + group.name + "': rate must be > 0 Hz");
  }
  const auto units = cia402::Units::from(drive.gear_ratio, drive.encoder_counts_per_rev);
  std::vector<ObjectWrite> writes;

  const auto mode = drive.mode == hal::CommandMode::kPosition
                        ? cia402::Mode::kCyclicSynchronousPosition
                        : cia402::Mode::kCyclicSynchronousVelocity;
  writes.push_back({cia402::kModesOfOperation,
                    static_cast<std::uint8_t>(static_cast<std::int8_t>(mode)), 1, true});

  const hal::JointLimits& limits = joint.limits;
  std::int64_t low =
      checked_counts(limits.min_position_rad * units.counts_per_rad, name + " min position");
  std::int64_t high =
      checked_counts(limits.max_position_rad * units.counts_per_rad, name + " max position");
  if (low > high) std::swap(low, high);  // A negative gear ratio turns the drive the other way.
  writes.push_back({cia402::kMinSoftwarePositionLimit,
                    static_cast<std::uint32_t>(static_cast<std::int32_t>(low)), 4, true});
  writes.push_back({cia402::kMaxSoftwarePositionLimit,
                    static_cast<std::uint32_t>(static_cast<std::int32_t>(high)), 4, true});

  if (limits.max_velocity_rad_s > 0.0) {
    const std::int64_t velocity = checked_counts(
        std::abs(limits.max_velocity_rad_s * units.counts_per_rad), name + " max velocity");
    writes.push_back({cia402::kMaxProfileVelocity, static_cast<std::uint32_t>(velocity), 4});
  }
  if (drive.following_error_window_rad > 0.0) {
    const std::int64_t window =
        checked_counts(std::abs(drive.following_error_window_rad * units.counts_per_rad),
                       name + " following error window");
    writes.push_back({cia402::kFollowingErrorWindow, static_cast<std::uint32_t>(window), 4});
  }

  const double heartbeat_ms = std::round(settings.heartbeat_period_s * 1000.0);
  if (!(heartbeat_ms >= 0.0 && heartbeat_ms <= 65535.0)) {
    throw std::invalid_argument("joint group '" + group.name + "': heartbeat period " +
                                std::to_string(settings.heartbeat_period_s) +
                                " s does not fit 0x1017 (0 .. 65.535 s)");
  }
  writes.push_back(
      {ObjectAddress{kProducerHeartbeatTime, 0}, static_cast<std::uint32_t>(heartbeat_ms), 2});

  const InterpolationPeriod period = interpolation_period(1.0 / rate_hz);
  writes.push_back({cia402::kInterpolationTimePeriod, period.value, 1});
  writes.push_back(
      {cia402::kInterpolationTimeIndex, static_cast<std::uint8_t>(period.index), 1, true});
  return writes;
}

std::vector<ObjectWrite> homing_parameter_writes(const hal::JointInfo& joint,
                                                 const JointDriveInfo& drive) {
  if (!drive.homing) return {};
  check_drive_units(joint, drive);
  const HomingSettings& homing = *drive.homing;
  const std::string name = "joint '" + joint.name + "' homing";
  if (homing.method < -128 || homing.method > 127) {
    throw std::invalid_argument(name + ": method " + std::to_string(homing.method) +
                                " does not fit 0x6098 (INTEGER8)");
  }
  const auto units = cia402::Units::from(drive.gear_ratio, drive.encoder_counts_per_rev);
  const auto unsigned_counts = [&](double value, const char* what) {
    return static_cast<std::uint32_t>(
        checked_counts(std::abs(value * units.counts_per_rad), name + " " + what));
  };
  const std::int64_t offset =
      checked_counts(homing.offset_rad * units.counts_per_rad, name + " offset");
  return {
      {cia402::kHomingMethod, static_cast<std::uint8_t>(static_cast<std::int8_t>(homing.method)), 1,
       true},
      {cia402::kHomingSwitchSpeed, unsigned_counts(homing.switch_speed_rad_s, "switch speed"), 4},
      {cia402::kHomingZeroSpeed, unsigned_counts(homing.zero_speed_rad_s, "zero speed"), 4},
      {cia402::kHomingAcceleration, unsigned_counts(homing.acceleration_rad_s2, "acceleration"), 4},
      {cia402::kHomeOffset, static_cast<std::uint32_t>(static_cast<std::int32_t>(offset)), 4, true},
  };
}

}  // namespace cambio::canopen
