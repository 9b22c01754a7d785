#pragma once

#include <cstdint>

namespace cambio::ros2 {

/// builtin_interfaces/Time: whole seconds and the nanoseconds past them (always in [0, 1e9)).
struct RosTime {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
};

/// The run's clock (ns) as ROS time: simulated time as it is (a lockstep run's /clock starts at
/// zero, as a ROS 2 simulator's does), wall time shifted onto the Unix epoch by `epoch_offset_ns`.
/// A time before the epoch or past 2038 (int32 seconds) is clamped to the nearest it can say.
constexpr RosTime to_ros_time(std::int64_t clock_ns, std::int64_t epoch_offset_ns = 0) {
  constexpr std::int64_t kNsPerS = 1'000'000'000;
  constexpr std::int64_t kLastNs = std::int64_t{INT32_MAX} * kNsPerS + (kNsPerS - 1);
  std::int64_t ns = clock_ns;
  // Saturating add: neither term comes from outside, but a huge one must not wrap.
  if (epoch_offset_ns > 0 && ns > INT64_MAX - epoch_offset_ns) {
    ns = INT64_MAX;
  } else {
    ns += epoch_offset_ns;
  }
  if (ns < 0) ns = 0;
  if (ns > kLastNs) ns = kLastNs;
  return {static_cast<std::int32_t>(ns / kNsPerS), static_cast<std::uint32_t>(ns % kNsPerS)};
}

/// ROS time back on the run's clock (ns): the inverse of to_ros_time within its range.
constexpr std::int64_t from_ros_time(RosTime time, std::int64_t epoch_offset_ns = 0) {
  return std::int64_t{time.sec} * 1'000'000'000 + std::int64_t{time.nanosec} - epoch_offset_ns;
}

}  // namespace cambio::ros2
