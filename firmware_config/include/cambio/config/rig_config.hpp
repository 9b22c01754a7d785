#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/config/camera_device_config.hpp"
#include "cambio/config/config_error.hpp"
#include "cambio/config/render_device.hpp"
#include "cambio/hal/camera.hpp"

namespace cambio::config {

/// A position and orientation of a child frame in its parent frame: translation in metres, then
/// roll-pitch-yaw (rad) applied as R = Rz(yaw) * Ry(pitch) * Rx(roll) (URDF's convention).
struct Pose {
  std::array<double, 3> xyz_m{0.0, 0.0, 0.0};
  std::array<double, 3> rpy_rad{0.0, 0.0, 0.0};
};

enum class ServoCommandMode : std::uint8_t { kPosition, kVelocity };

/// The noisy servo model of the sim (the paper's "controlled Gaussian errors") and what a real
/// drive is commanded in.
struct ServoConfig {
  ServoCommandMode command = ServoCommandMode::kPosition;
  double dead_time_s = 0.0;                 ///< Delay between a command and its first effect.
  double motion_noise_std_rad = 0.0;        ///< Gaussian error added to each executed motion.
  std::int64_t encoder_counts_per_rev = 0;  ///< Encoder quantisation; 0 = ideal encoder.
  double backlash_rad = 0.0;                ///< Dead band on direction reversal; 0 = none.
};

/// CANopen CiA 402 settings of the drive behind a joint (used when its group's backend is
/// socketcan, or by the sim's virtual CAN rig).
struct JointCanConfig {
  int node_id = 0;                          ///< 1..127.
  double gear_ratio = 1.0;                  ///< Motor turns per joint turn.
  std::int64_t encoder_counts_per_rev = 0;  ///< Motor encoder counts per motor turn.
  /// CiA 402 following error window (0x6065); 0 = leave the drive's own setting.
  double following_error_window_rad = 0.0;
  /// `homing: {method, ...}` (CiA 402 homing mode 6, canopen::HomingSettings); none (`homing:
  /// none`, the default) for an absolute encoder.
  struct Homing {
    int method = 0;
    double switch_speed_rad_s = 0.0;
    double zero_speed_rad_s = 0.0;
    double acceleration_rad_s2 = 0.0;
    double offset_rad = 0.0;
    double timeout_s = 0.0;
  };
  std::optional<Homing> homing;
  /// What only the virtual drive (`cambio virtual-rig`) reads: where its emulated limit switch and
  /// encoder index pulse are, in the joint's own angle (`virtual_drive: {home_switch_deg,
  /// index_pulse_deg}`). The index pulse repeats every motor turn (360 deg / gear_ratio).
  std::optional<double> virtual_home_switch_rad;
  std::optional<double> virtual_index_pulse_rad;
};

/// A joint's max_tracking_error_rad when its rig entry gives none: 20 deg, well above what a
/// command leads a joint at its limits (the shipped experiments peak at 7.5 deg: an eye in a
/// 430 deg/s saccade, a shoulder in a reach), well below a stale target's jump (the wind-up seen
/// on a held head was 25 deg).
inline constexpr double kDefaultMaxTrackingError_rad = 20.0 * std::numbers::pi / 180.0;

/// A revolute joint (every joint of the Câmbio robot turns, the grippers' fingers included).
struct JointConfig {
  std::string name;
  std::string group;
  /// The link this joint hangs from: "base" or the name of another joint (each joint moves a
  /// link named after it).
  std::string parent = "base";
  Pose origin;  ///< Joint frame in the parent link frame at zero.
  /// Unit vector in the joint frame. The loader normalises the file's `axis` (so [0, 0, 2] is
  /// accepted as [0, 0, 1]) and refuses a zero vector.
  std::array<double, 3> axis{0.0, 0.0, 1.0};
  double min_position_rad = 0.0;
  double max_position_rad = 0.0;
  double max_velocity_rad_s = 0.0;
  double max_acceleration_rad_s2 = 0.0;
  double max_effort_nm = 0.0;  ///< 0 = not limited by the stack (the drive limits it).
  /// How far a controller's command may lead this joint's measured position before it is a
  /// fault of that controller (a drive that does not follow while nothing says so): the
  /// `max_tracking_error_deg/_rad` key, by default kDefaultMaxTrackingError_rad or the joint's
  /// travel if that is shorter.
  double max_tracking_error_rad = 0.0;
  double initial_position_rad = 0.0;
  ServoConfig servo;
  std::optional<JointCanConfig> can;
};

/// What a CANopen group needs besides its joints' drives (groups.<g>.can); the defaults are
/// canopen::CanGroupSettings'.
struct JointGroupCanConfig {
  double heartbeat_period_s = 0.1;  ///< Each drive's heartbeat (0x1017), from heartbeat_period_ms.
  int stale_after_missed_syncs = 3;
  double sdo_timeout_s = 0.1;  ///< From sdo_timeout_ms.
  /// Optional PDO objects (feedforward: [velocity, effort], feedback: [velocity, effort]).
  bool velocity_feedforward = false;
  bool effort_feedforward = false;
  bool velocity_feedback = false;
  bool effort_feedback = false;
};

struct JointGroupConfig {
  std::string name;
  /// The backend driving the group, by the name it registers with ("sim", "socketcan"); which
  /// names this build carries is the application's to check, at `backend_at`.
  std::string backend;
  ConfigIssue backend_at;  ///< Where the backend is named (for errors found after loading).
  std::vector<std::string> joints;  ///< Order of the group's read()/write() spans.
  std::string can_bus;              ///< Name in RigConfig::can_buses; needed by socketcan.
  /// The group's joint-loop rate (a CAN group's SYNC rate): its rate_hz key, else
  /// loops.joint.rate_hz. Groups of one rate share a joint loop.
  double rate_hz = 0.0;
  bool own_rate = false;  ///< rate_hz came from the group's own key.
  JointGroupCanConfig can;
};

enum class PixelFormatConfig : std::uint8_t { kGrey8, kRgb8 };

/// Sim cameras only: foveated rendering. The eye's field is rendered at 1 / periphery_downscale of
/// its resolution and shown upsampled (each rendered pixel a periphery_downscale square), with a
/// centred fovea_px x fovea_px window rendered at full resolution over it. The retina reads full
/// resolution only near the fixation point (its levels of blocks finer than the downscale), so a
/// fovea that covers those levels serves it at a fraction of the pixels. Off when the downscale
/// is 1.
struct SimFoveationConfig {
  int periphery_downscale = 1;
  int fovea_px = 0;
  bool enabled() const { return periphery_downscale > 1; }
  /// Whether it tiles a width x height image: the downscale divides both sides and the fovea,
  /// no larger than the shorter side, sits centred on whole pixels. Off always fits.
  bool fits(int width_px, int height_px) const;
};

struct CameraConfig {
  std::string name;
  std::string backend = "sim";  ///< As JointGroupConfig::backend; default "sim".
  ConfigIssue backend_at;
  /// Link the camera is mounted on: "base" or a joint's name.
  std::string parent;
  /// Pose of the camera's optical frame (z forward, x right, y down: OpenCV's) in the parent.
  Pose mount;
  int width_px = 0;
  int height_px = 0;
  double focal_x_px = 0.0;
  double focal_y_px = 0.0;
  double principal_x_px = 0.0;  ///< From the top-left pixel's centre.
  double principal_y_px = 0.0;
  /// The `distortion` key, or the rig's camera_calibration file; zero (a pinhole) when absent.
  hal::PlumbBobDistortion distortion;
  PixelFormatConfig format = PixelFormatConfig::kRgb8;
  double image_noise_std = 0.0;  ///< Sim: Gaussian noise on grey levels (0-255 scale).
  SimFoveationConfig sim_foveation;
  CameraDeviceConfig device;  ///< A real camera's device node and mode (v4l2).
};

struct StereoConfig {
  std::string left_camera;
  std::string right_camera;
  double baseline_m = 0.0;  ///< Distance between the two eyes' pan axes.
};

struct TouchSensorConfig {
  std::string name;
  std::string backend = "sim";  ///< As JointGroupConfig::backend; default "sim".
  ConfigIssue backend_at;
  std::string parent;  ///< The link (joint name) whose geometry is the end effector.
  /// The fingertips the hand reaches and touches with: the middle of one fingertip's front face
  /// in the parent (gripper) link's frame at zero opening, x along the finger, y off the
  /// gripper's midline; the other finger mirrors it to -y. The sim builds its fingers from it.
  double fingertip_x_m = 0.082;
  double fingertip_y_m = 0.008;
};

struct CanBusConfig {
  std::string name;
  std::string interface;  ///< Kernel interface, e.g. "can0", "vcan0".
  std::int64_t bitrate_bit_s = 1'000'000;
  bool fd = false;
  std::int64_t data_bitrate_bit_s = 0;  ///< FD data phase; 0 when fd is false.
};

enum class OverrunPolicy : std::uint8_t {
  kSkip,     ///< Drop the missed cycles; next deadline is the next one in the future.
  kCatchUp,  ///< Run the missed cycles back to back.
};

struct LoopConfig {
  std::string name;
  double rate_hz = 0.0;
  int priority = 0;  ///< SCHED_FIFO priority 1..99; 0 = normal scheduling.
  int cpu = -1;      ///< CPU to pin the loop's thread to; -1 = any.
  OverrunPolicy overrun = OverrunPolicy::kSkip;
  /// Joint loop only (0 elsewhere): targets older than this are stale and the joints hold.
  double command_timeout_s = 0.0;
  /// Joint loop only (0 elsewhere): a joint reading older than this is flagged stale and the
  /// loop sends no motion until fresh readings arrive.
  double feedback_timeout_s = 0.0;
};

struct SimConfig {
  double physics_rate_hz = 1000.0;
  /// Where the cameras render (CAMBIO_EGL_DEVICE overrides it): see RenderDevice.
  RenderDevice render_device;
};

struct RuntimeConfig {
  bool lock_memory = false;  ///< mlockall(MCL_CURRENT | MCL_FUTURE) in the realtime executor.
};

/// A whole robot, as loaded from rigs/*.yaml. Const after loading; everything else is derived
/// from it (the sim's MJCF, the CAN PDO maps, the HAL infos).
struct RigConfig {
  std::string source_file;  ///< Where it was loaded from, for messages.
  std::string name;
  std::vector<JointConfig> joints;
  std::vector<JointGroupConfig> groups;
  std::vector<CameraConfig> cameras;
  std::optional<StereoConfig> stereo;
  std::vector<TouchSensorConfig> touch_sensors;
  std::vector<CanBusConfig> can_buses;
  std::vector<LoopConfig> loops;  ///< Always holds joint, control, perception and camera.
  SimConfig sim;
  RuntimeConfig runtime;

  const JointConfig* find_joint(const std::string& joint_name) const;
  const JointGroupConfig* find_group(const std::string& group_name) const;
  const CameraConfig* find_camera(const std::string& camera_name) const;
  const LoopConfig* find_loop(const std::string& loop_name) const;
  const CanBusConfig* find_can_bus(const std::string& bus_name) const;

  /// Where the rig file's joint, group, camera, touch sensor and bus entries and their keys are,
  /// by key path: for checks made after loading by a layer that knows what the loader cannot (a
  /// backend's check names the key it refuses).
  std::map<std::string, ConfigIssue, std::less<>> locations;
  /// The location of `key_path`, else of the nearest enclosing entry recorded (a missing key is
  /// reported at its map), with `key_path` and `message` as given.
  ConfigIssue locate(std::string_view key_path, std::string message) const;
};

}  // namespace cambio::config
