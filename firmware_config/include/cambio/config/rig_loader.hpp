#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cambio/config/map_reader.hpp"
#include "cambio/config/rig_config.hpp"

namespace cambio::config {

/// Bounds the loader puts on values that size what the program allocates or counts; a rig that
/// loads stays within them, so no buffer they drive grows without bound.
///
/// Joints: the joint loop's frames are fixed-size arrays of control::kMaxJoints (32) entries
/// (and hal::JointStateTap's of 32); a test keeps the three equal.
inline constexpr std::size_t kMaxJoints = 32;
/// Camera width and height: the sim renders into MuJoCo's offscreen buffer, sized to the largest
/// camera, and holds several copies of each frame (48 MiB per 4096 x 4096 RGB copy).
inline constexpr int kMaxCameraSide_px = 4096;
/// All cameras' pixels together: two cameras (a stereo pair) of the largest size.
inline constexpr std::int64_t kMaxCameraPixels =
    std::int64_t{2} * kMaxCameraSide_px * kMaxCameraSide_px;
/// A servo's dead time: the sim delays commands through a line of dead_time_s x physics_rate_hz
/// entries per joint (100,000 at the highest physics rate). A drive's is milliseconds.
inline constexpr double kMaxDeadTime_s = 1.0;
/// Loop rates: the runtime counts deadlines in nanoseconds, and a run's cycles are its duration
/// times its rates; beyond these a rate is a typo, not a plan.
inline constexpr double kMinRate_hz = 0.1;
inline constexpr double kMaxRate_hz = 100'000.0;
/// The physics rate's floor: the sim's encoders difference positions over a 10 ms window, at
/// least one step long.
inline constexpr double kMinPhysicsRate_hz = 100.0;
/// CPU numbers a loop may be pinned to: the kernel's CPU sets hold CPU_SETSIZE (1024).
inline constexpr int kMaxCpu = 1023;

/// Loads and validates a rig file (rigs/*.yaml), overrides applied first. Throws ConfigError
/// with every problem found: unknown or missing keys, wrong types, out-of-range values and
/// inconsistent settings (a lower limit above the upper one, a rate of 0, a group naming an
/// unknown joint, a joint in two groups, a stereo baseline that disagrees with the eyes' joint
/// origins, ...). What a backend needs of its own sections (a CAN group's bus, unique node ids,
/// the bus load) is that backend's check (hal::BackendFactory::check), made by the application.
RigConfig load_rig(const std::string& path, const std::vector<ConfigOverride>& overrides = {});
/// The same from YAML text (tests); `name` stands for the file in messages.
RigConfig load_rig_from_string(const std::string& yaml, const std::string& name,
                               const std::vector<ConfigOverride>& overrides = {});
/// Reads a rig from an already loaded document (for callers that embed a rig).
RigConfig read_rig(MapReader root, const std::string& file);

/// Default loops when the rig file does not define them: joint 1000 Hz, control 200 Hz,
/// perception 60 Hz, camera 30 Hz.
std::vector<LoopConfig> default_loops();

}  // namespace cambio::config
