#include "cambio/config/rig_loader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "cambio/config/camera_calibration.hpp"
#include "format.hpp"

namespace cambio::config {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr std::string_view kBase = "base";
/// Stereo baseline agreement with the eyes' joint origins, in metres.
constexpr double kBaselineTolerance_m = 1e-6;
// The joint loop's watchdogs: 20 control periods for targets and 20 joint periods for feedback
// at the default rates; an hour bounds them (a loop that waits longer is not watching).
constexpr double kDefaultCommandTimeout_s = 0.1;
constexpr double kDefaultFeedbackTimeout_s = 0.02;
constexpr double kMaxJointTimeout_s = 3600.0;

/// Counts issues so a consistency check runs only on values that were read cleanly (and does
/// not pile a second message on a value already reported).
class CleanRead {
 public:
  explicit CleanRead(const MapReader& reader)
      : issues_(reader.issues()), start_(issues_->issues().size()) {}
  bool clean() const { return issues_->issues().size() == start_; }

 private:
  std::shared_ptr<IssueList> issues_;
  std::size_t start_;
};

/// `expected one of a, b, c, found "x"` with a "did you mean" when one name is close.
std::string unknown_name_message(std::string_view what, const std::string& name,
                                 const std::vector<std::string>& known) {
  std::string message = "expected " + std::string(what);
  if (known.empty()) {
    message += " (there are none)";
  } else {
    message += " (" + join(known) + ")";
  }
  message += ", found " + in_quotes(name);
  if (const auto suggestion = closest_name(name, known)) {
    message += "; did you mean " + in_quotes(*suggestion) + "?";
  }
  return message;
}

/// The key an angle was given under: "<stem>_deg" or "<stem>_rad".
std::string angle_key(const MapReader& reader, const std::string& stem) {
  return reader.has(stem + "_deg") ? stem + "_deg" : stem + "_rad";
}

/// An angle in the unit its key used, for messages.
std::string format_angle(double angle_rad, const std::string& key) {
  return key.ends_with("_deg") ? format_number(angle_rad * kDegPerRad) + " deg"
                               : format_number(angle_rad) + " rad";
}

struct JointEntry {
  MapReader reader;
  std::optional<MapReader> can;
};

struct GroupEntry {
  MapReader reader;
};

/// joints.<j>.can.homing: `none` (the default: an absolute encoder) or CiA 402 homing's
/// settings. Speeds above the joint's own limit are refused: the drive would move faster while
/// homing than the rig allows it to be driven.
std::optional<JointCanConfig::Homing> read_joint_homing(MapReader& can, double max_velocity_rad_s) {
  if (!can.has("homing")) return std::nullopt;
  if (!can.is_map("homing")) {
    (void)can.choice("homing", {"none"});
    return std::nullopt;
  }
  MapReader h = can.map("homing");
  JointCanConfig::Homing homing;
  const CleanRead method_read(h);
  homing.method = static_cast<int>(h.integer(
      "method", Range::closed(-128, 37).because("0x6098 is an INTEGER8: CiA 402's methods are "
                                                "1..37, a vendor's own are negative")));
  if (method_read.clean() && homing.method == 0) {
    h.error("method",
            "expected a homing method (e.g. 17 limit switch, 33 index pulse), found 0 "
            "(no homing); write `homing: none` for a joint that does not home");
  }
  const Range speed = max_velocity_rad_s > 0.0
                          ? Range{0.0, max_velocity_rad_s, true, false}.because(
                                "at most the joint's max_velocity_rad_s")
                          : Range::positive();
  homing.switch_speed_rad_s = h.number("switch_speed_rad_s", speed);
  homing.zero_speed_rad_s = h.number("zero_speed_rad_s", speed);
  homing.acceleration_rad_s2 = h.number("acceleration_rad_s2", Range::positive());
  homing.offset_rad = h.angle_rad_or("offset", 0.0);
  homing.timeout_s =
      h.number("timeout_s", Range{0.0, 3600.0, true, false}.because("a homing run takes seconds"));
  h.finish();
  return homing;
}

JointConfig read_joint(const std::string& name, MapReader& r,
                       std::optional<MapReader>& can_reader) {
  JointConfig joint;
  joint.name = name;
  if (name == kBase)
    r.error("", "\"base\" names the robot's root link; give the joint another name");
  joint.group = r.text("group");
  joint.parent = r.text_or("parent", std::string(kBase));
  joint.origin.xyz_m = r.vector3_or("origin_xyz_m", {0.0, 0.0, 0.0});
  joint.origin.rpy_rad = r.angles3_rad_or("origin_rpy", {0.0, 0.0, 0.0});

  {
    const CleanRead axis_read(r);
    const auto axis = r.vector3("axis");
    if (axis_read.clean()) {
      const double norm = std::hypot(axis[0], axis[1], axis[2]);
      if (norm < 1e-9) {
        r.error("axis", "expected a non-zero axis vector, found [" + format_number(axis[0]) + ", " +
                            format_number(axis[1]) + ", " + format_number(axis[2]) + "]");
      } else {
        joint.axis = {axis[0] / norm, axis[1] / norm, axis[2] / norm};
      }
    }
  }

  const CleanRead limits_read(r);
  joint.min_position_rad = r.angle_rad("min_position");
  joint.max_position_rad = r.angle_rad("max_position");
  const bool limits_clean = limits_read.clean();
  if (limits_clean && joint.min_position_rad >= joint.max_position_rad) {
    const std::string min_key = angle_key(r, "min_position");
    const std::string max_key = angle_key(r, "max_position");
    r.error(min_key, "expected a lower limit below " + max_key + " (" +
                         format_angle(joint.max_position_rad, max_key) + "), found " +
                         format_angle(joint.min_position_rad, min_key));
  }
  joint.max_velocity_rad_s = r.number("max_velocity_rad_s", Range::positive());
  joint.max_acceleration_rad_s2 = r.number("max_acceleration_rad_s2", Range::positive());
  joint.max_effort_nm = r.number_or("max_effort_nm", 0.0, Range::non_negative());
  {
    // A bound wider than the joint's travel could never be met: it is refused, and the default
    // shrinks to the travel.
    const double travel_rad = limits_clean && joint.min_position_rad < joint.max_position_rad
                                  ? joint.max_position_rad - joint.min_position_rad
                                  : std::numeric_limits<double>::infinity();
    const CleanRead tracking_read(r);
    joint.max_tracking_error_rad =
        r.angle_rad_or("max_tracking_error", std::min(kDefaultMaxTrackingError_rad, travel_rad),
                       Range::positive());
    if (tracking_read.clean() && joint.max_tracking_error_rad > travel_rad) {
      const std::string key = angle_key(r, "max_tracking_error");
      r.error(key, "expected at most the joint's travel (" + format_angle(travel_rad, key) +
                       "), found " + format_angle(joint.max_tracking_error_rad, key));
    }
  }

  const bool has_initial = r.has("initial_position_deg") || r.has("initial_position_rad");
  const CleanRead initial_read(r);
  joint.initial_position_rad = r.angle_rad_or("initial_position", 0.0);
  if (limits_clean && joint.min_position_rad < joint.max_position_rad) {
    if (!has_initial) {
      // Zero unless the limits exclude it (a gripper that opens from 10 deg, say).
      joint.initial_position_rad = std::clamp(0.0, joint.min_position_rad, joint.max_position_rad);
    } else if (initial_read.clean() && (joint.initial_position_rad < joint.min_position_rad ||
                                        joint.initial_position_rad > joint.max_position_rad)) {
      const std::string key = angle_key(r, "initial_position");
      r.error(key, "expected a position within the limits [" +
                       format_angle(joint.min_position_rad, key) + ", " +
                       format_angle(joint.max_position_rad, key) + "], found " +
                       format_angle(joint.initial_position_rad, key));
    }
  }

  if (auto servo = r.optional_map("servo")) {
    joint.servo.command =
        servo->choice_or("command", {"position", "velocity"}, "position") == "velocity"
            ? ServoCommandMode::kVelocity
            : ServoCommandMode::kPosition;
    joint.servo.dead_time_s = servo->number_or(
        "dead_time_s", 0.0,
        Range::closed(0.0, kMaxDeadTime_s)
            .because("a drive's dead time is milliseconds; the sim delays commands through "
                     "dead_time_s x physics_rate_hz entries per joint"));
    joint.servo.motion_noise_std_rad =
        servo->angle_rad_or("motion_noise_std", 0.0, Range::non_negative());
    joint.servo.encoder_counts_per_rev =
        servo->integer_or("encoder_counts_per_rev", 0, Range::non_negative());
    joint.servo.backlash_rad = servo->angle_rad_or("backlash", 0.0, Range::non_negative());
    servo->finish();
  }

  can_reader = r.optional_map("can");
  if (can_reader) {
    JointCanConfig can;
    can.node_id = static_cast<int>(can_reader->integer("node_id", Range::closed(1, 127)));
    can.gear_ratio = can_reader->number_or("gear_ratio", 1.0, Range::positive());
    can.encoder_counts_per_rev = can_reader->integer(
        "encoder_counts_per_rev", Range{1.0, std::numeric_limits<double>::infinity()});
    can.following_error_window_rad =
        can_reader->angle_rad_or("following_error_window", 0.0, Range::non_negative());
    can.homing = read_joint_homing(*can_reader, joint.max_velocity_rad_s);
    if (auto virtual_drive = can_reader->optional_map("virtual_drive")) {
      if (virtual_drive->has("home_switch_deg") || virtual_drive->has("home_switch_rad")) {
        can.virtual_home_switch_rad = virtual_drive->angle_rad("home_switch");
      }
      if (virtual_drive->has("index_pulse_deg") || virtual_drive->has("index_pulse_rad")) {
        can.virtual_index_pulse_rad = virtual_drive->angle_rad("index_pulse");
      }
      virtual_drive->finish();
    }
    can_reader->finish();
    joint.can = can;
  }
  r.finish();
  return joint;
}

Range rate_range() {
  return Range::closed(kMinRate_hz, kMaxRate_hz)
      .because("a run's cycles are its duration times its rates");
}

/// Which of `allowed` a list names (`feedforward: [velocity, effort]`), each at most once.
std::set<std::string> read_flag_list(MapReader& r, std::string_view key,
                                     const std::vector<std::string>& allowed) {
  std::set<std::string> flags;
  const auto items = r.strings_or(key, {});
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (std::find(allowed.begin(), allowed.end(), items[i]) == allowed.end()) {
      r.error(key, i, unknown_name_message("a mapped object", items[i], allowed));
    } else if (!flags.insert(items[i]).second) {
      r.error(key, i,
              "expected each of " + join(allowed) + " at most once, found " + in_quotes(items[i]) +
                  " again");
    }
  }
  return flags;
}

JointGroupCanConfig read_group_can(MapReader& r) {
  JointGroupCanConfig can;
  // 0x1017 holds the heartbeat period as a 16-bit count of ms; 0 would switch it off, and with
  // it the master's detection of a lost drive.
  can.heartbeat_period_s =
      static_cast<double>(r.integer_or(
          "heartbeat_period_ms", std::llround(can.heartbeat_period_s * 1000),
          Range::closed(1, 65535).because("0x1017 is a 16-bit count of ms; 0 would switch the "
                                          "heartbeat, and loss detection, off"))) /
      1000.0;
  can.stale_after_missed_syncs = static_cast<int>(r.integer_or(
      "stale_after_missed_syncs", can.stale_after_missed_syncs, Range::closed(1, 1000)));
  can.sdo_timeout_s =
      static_cast<double>(r.integer_or("sdo_timeout_ms", std::llround(can.sdo_timeout_s * 1000),
                                       Range::closed(1, 60'000))) /
      1000.0;
  const std::vector<std::string> objects{"velocity", "effort"};
  const auto feedforward = read_flag_list(r, "feedforward", objects);
  can.velocity_feedforward = feedforward.contains("velocity");
  can.effort_feedforward = feedforward.contains("effort");
  const auto feedback = read_flag_list(r, "feedback", objects);
  can.velocity_feedback = feedback.contains("velocity");
  can.effort_feedback = feedback.contains("effort");
  r.finish();
  return can;
}

/// A backend is named as it registers itself: lower-case letters, digits and '_', starting with
/// a letter. Which names exist is not the config layer's to know: the application checks them
/// against the backends it carries (at JointGroupConfig::backend_at).
std::string read_backend_name(MapReader& r, const std::optional<std::string>& fallback) {
  std::string name = fallback ? r.text_or("backend", *fallback) : r.text("backend");
  if (!r.has("backend")) return name;
  const bool well_formed = !name.empty() && name.size() <= 64 &&
                           std::islower(static_cast<unsigned char>(name[0])) &&
                           std::all_of(name.begin(), name.end(), [](char c) {
                             return std::islower(static_cast<unsigned char>(c)) ||
                                    std::isdigit(static_cast<unsigned char>(c)) || c == '_';
                           });
  if (!well_formed) {
    r.error("backend",
            "expected a backend's name (at most 64 lower-case letters, digits and '_', starting "
            "with a letter, e.g. sim or socketcan), found '" +
                name + "'");
  }
  return name;
}

JointGroupConfig read_group(const std::string& name, MapReader& r) {
  JointGroupConfig group;
  group.name = name;
  group.backend = read_backend_name(r, std::nullopt);
  group.backend_at = r.location_of("backend");
  group.joints = r.strings("joints");
  if (r.has("joints") && group.joints.empty()) {
    r.error("joints", "expected a list of at least one joint name, found an empty list");
  }
  group.can_bus = r.text_or("can_bus", "");
  group.own_rate = r.has("rate_hz");
  if (group.own_rate) group.rate_hz = r.number("rate_hz", rate_range());
  if (auto can = r.optional_map("can")) group.can = read_group_can(*can);
  r.finish();
  return group;
}

// The fovea is centred on whole pixels and the periphery's pixels tile the image exactly, so the
// composed frame has no seam or half-pixel shift.
void read_sim_foveation(MapReader& r, CameraConfig& camera, bool size_clean) {
  SimFoveationConfig& foveation = camera.sim_foveation;
  const CleanRead read(r);
  foveation.periphery_downscale =
      static_cast<int>(r.integer("periphery_downscale", Range::closed(1, 16)));
  foveation.fovea_px = static_cast<int>(r.integer("fovea_px", Range::closed(8, 4096)));
  r.finish();
  if (!size_clean || !read.clean()) return;
  const int s = foveation.periphery_downscale;
  const int w = camera.width_px;
  const int h = camera.height_px;
  if (w % s != 0 || h % s != 0) {
    r.error("periphery_downscale", "expected a divisor of the " + std::to_string(w) + "x" +
                                       std::to_string(h) + " image's width and height, found " +
                                       std::to_string(s));
  }
  const int f = foveation.fovea_px;
  if (f > std::min(w, h) || (w - f) % 2 != 0 || (h - f) % 2 != 0) {
    r.error("fovea_px", "expected at most " + std::to_string(std::min(w, h)) +
                            " px, with the same parity as the image's width and height (" +
                            std::to_string(w) + "x" + std::to_string(h) +
                            ") so that it is centred on whole pixels, found " + std::to_string(f));
  }
}

CameraConfig read_camera(const std::string& name, MapReader& r) {
  CameraConfig camera;
  camera.name = name;
  camera.backend = read_backend_name(r, camera.backend);
  camera.backend_at = r.location_of("backend");
  camera.parent = r.text("parent");
  camera.mount.xyz_m = r.vector3_or("origin_xyz_m", {0.0, 0.0, 0.0});
  camera.mount.rpy_rad = r.angles3_rad_or("origin_rpy", {0.0, 0.0, 0.0});
  const CleanRead size_read(r);
  const Range side_range =
      Range::closed(1, kMaxCameraSide_px)
          .because(
              "the sim renders into an offscreen buffer of the largest camera's size and "
              "keeps several copies of each frame");
  camera.width_px = static_cast<int>(r.integer("width_px", side_range));
  camera.height_px = static_cast<int>(r.integer("height_px", side_range));
  const bool size_clean = size_read.clean();

  // Either focal_px (square pixels) or focal_x_px and focal_y_px. Every branch reads all three
  // keys so that each counts as accepted (for "did you mean") whichever form the file uses.
  const bool has_focal = r.has("focal_px");
  const bool has_xy = r.has("focal_x_px") || r.has("focal_y_px");
  if (has_focal && has_xy) {
    r.number_or("focal_px", 0.0, Range::positive());
    r.number_or("focal_x_px", 0.0, Range::positive());
    r.number_or("focal_y_px", 0.0, Range::positive());
    r.error(r.has("focal_x_px") ? "focal_x_px" : "focal_y_px",
            "expected either focal_px or focal_x_px and focal_y_px, found both");
  } else if (has_xy) {
    r.number_or("focal_px", 0.0);
    camera.focal_x_px = r.number("focal_x_px", Range::positive());
    camera.focal_y_px = r.number("focal_y_px", Range::positive());
  } else {
    camera.focal_x_px = camera.focal_y_px = r.number("focal_px", Range::positive());
    r.number_or("focal_x_px", 0.0);
    r.number_or("focal_y_px", 0.0);
  }

  // Centred by default: the pixel grid's middle, counted from the top-left pixel's centre.
  camera.principal_x_px = (camera.width_px - 1) / 2.0;
  camera.principal_y_px = (camera.height_px - 1) / 2.0;
  if (r.has("principal_point_px")) {
    const CleanRead point_read(r);
    const auto point = r.numbers("principal_point_px");
    if (point_read.clean() && point.size() != 2) {
      r.error("principal_point_px", "expected a list of 2 numbers [cx, cy], found a list of " +
                                        std::to_string(point.size()));
    } else if (point_read.clean()) {
      camera.principal_x_px = point[0];
      camera.principal_y_px = point[1];
      // Pixel centres run from 0 to size - 1; the image's edges lie half a pixel further out.
      const double max_x = camera.width_px - 0.5;
      const double max_y = camera.height_px - 0.5;
      if (size_clean &&
          (point[0] < -0.5 || point[0] > max_x || point[1] < -0.5 || point[1] > max_y)) {
        r.error("principal_point_px",
                "expected a point inside the " + std::to_string(camera.width_px) + "x" +
                    std::to_string(camera.height_px) + " image (x in [-0.5, " +
                    format_number(max_x) + "], y in [-0.5, " + format_number(max_y) +
                    "]), found [" + format_number(point[0]) + ", " + format_number(point[1]) + "]");
      }
    }
  }
  if (auto distortion = r.optional_map("distortion")) {
    camera.distortion = read_plumb_bob_distortion(*distortion);
  }
  camera.format = r.choice_or("format", {"grey8", "rgb8"}, "rgb8") == "grey8"
                      ? PixelFormatConfig::kGrey8
                      : PixelFormatConfig::kRgb8;
  camera.image_noise_std = r.number_or("image_noise_std", 0.0, Range::non_negative());
  if (auto foveation = r.optional_map("sim_foveation")) {
    read_sim_foveation(*foveation, camera, size_clean);
  }
  camera.device = read_camera_device(r);
  r.finish();
  return camera;
}

CanBusConfig read_can_bus(const std::string& name, MapReader& r) {
  CanBusConfig bus;
  bus.name = name;
  bus.interface = r.text("interface");
  // The kernel's rule for interface names (dev_valid_name): check-config looks the name up
  // under /sys/class/net, so it must not be a path.
  const bool valid_interface = bus.interface.size() <= 15 && bus.interface != "." &&
                               bus.interface != ".." &&
                               bus.interface.find_first_of("/: \t\n") == std::string::npos;
  if (!bus.interface.empty() && !valid_interface) {
    r.error("interface",
            "expected a network interface name (at most 15 characters, no '/', ':' "
            "or spaces), found " +
                in_quotes(bus.interface));
  }
  // Classic CAN's nominal (arbitration) bitrate tops out at 1 Mbit/s.
  bus.bitrate_bit_s = r.integer_or("bitrate_bit_s", 1'000'000, Range::closed(1'000, 1'000'000));
  bus.fd = r.boolean_or("fd", false);
  if (bus.fd) {
    const CleanRead data_read(r);
    bus.data_bitrate_bit_s = r.integer("data_bitrate_bit_s", Range::closed(1'000, 16'000'000));
    if (data_read.clean() && bus.data_bitrate_bit_s < bus.bitrate_bit_s) {
      r.error("data_bitrate_bit_s", "expected a data bitrate >= bitrate_bit_s (" +
                                        std::to_string(bus.bitrate_bit_s) + "), found " +
                                        std::to_string(bus.data_bitrate_bit_s));
    }
  } else if (r.has("data_bitrate_bit_s")) {
    r.integer_or("data_bitrate_bit_s", 0);
    r.error("data_bitrate_bit_s",
            "expected no data bitrate on a classic CAN bus (set fd: true for CAN FD), found one");
  }
  r.finish();
  return bus;
}

LoopConfig read_loop(const std::string& name, MapReader& r) {
  const auto defaults = default_loops();
  const auto standard = std::find_if(defaults.begin(), defaults.end(),
                                     [&](const LoopConfig& loop) { return loop.name == name; });
  LoopConfig loop;
  loop.name = name;
  loop.rate_hz = standard != defaults.end()
                     ? r.number_or("rate_hz", standard->rate_hz, rate_range())
                     : r.number("rate_hz", rate_range());
  loop.priority = static_cast<int>(r.integer_or("priority", 0, Range::closed(0, 99)));
  loop.cpu = static_cast<int>(r.integer_or(
      "cpu", -1, Range::closed(-1, kMaxCpu).because("-1: any; the kernel's CPU sets end there")));
  loop.overrun = r.choice_or("overrun", {"skip", "catch_up"}, "skip") == "catch_up"
                     ? OverrunPolicy::kCatchUp
                     : OverrunPolicy::kSkip;
  if (name == "joint") {
    const Range timeout_range{0.0, kMaxJointTimeout_s, true, false};
    loop.command_timeout_s =
        r.number_or("command_timeout_s", kDefaultCommandTimeout_s, timeout_range);
    loop.feedback_timeout_s =
        r.number_or("feedback_timeout_s", kDefaultFeedbackTimeout_s, timeout_range);
  }
  r.finish();
  return loop;
}

/// Every joint in exactly one group, and the group its own `group` key names.
void check_group_membership(RigConfig& rig, std::vector<JointEntry>& joints,
                            std::vector<GroupEntry>& groups,
                            const std::vector<std::string>& joint_names) {
  std::map<std::string, std::string> group_of;
  for (std::size_t g = 0; g < rig.groups.size(); ++g) {
    const auto& group = rig.groups[g];
    for (std::size_t i = 0; i < group.joints.size(); ++i) {
      const std::string& joint = group.joints[i];
      if (joint.empty()) continue;  // Already reported as not a name.
      if (rig.find_joint(joint) == nullptr) {
        groups[g].reader.error("joints", i, unknown_name_message("a joint", joint, joint_names));
        continue;
      }
      const auto [it, inserted] = group_of.emplace(joint, group.name);
      if (!inserted) {
        groups[g].reader.error("joints", i,
                               "expected each joint in one group only, found " + in_quotes(joint) +
                                   " again (already in group " + in_quotes(it->second) + ")");
      }
    }
  }
  std::vector<std::string> group_names;
  for (const auto& group : rig.groups) group_names.push_back(group.name);
  for (std::size_t j = 0; j < rig.joints.size(); ++j) {
    const auto& joint = rig.joints[j];
    if (joint.group.empty()) continue;
    const auto member = group_of.find(joint.name);
    if (member == group_of.end()) {
      if (rig.find_group(joint.group) == nullptr) {
        joints[j].reader.error("group", unknown_name_message("a group", joint.group, group_names));
      } else {
        joints[j].reader.error("",
                               "expected the joint in one group's joint list, found it in "
                               "none (add it to groups." +
                                   joint.group + ".joints)");
      }
    } else if (member->second != joint.group) {
      joints[j].reader.error("group", "expected " + in_quotes(member->second) + " (groups." +
                                          member->second + ".joints lists this joint), found " +
                                          in_quotes(joint.group));
    }
  }
}

/// Parents name "base" or a joint, and following them always ends at "base".
void check_kinematic_tree(const RigConfig& rig, std::vector<JointEntry>& joints,
                          const std::vector<std::string>& joint_names) {
  std::set<std::string> in_reported_cycle;
  for (std::size_t j = 0; j < rig.joints.size(); ++j) {
    const auto& joint = rig.joints[j];
    if (joint.parent != kBase && rig.find_joint(joint.parent) == nullptr) {
      std::vector<std::string> choices{std::string(kBase)};
      choices.insert(choices.end(), joint_names.begin(), joint_names.end());
      joints[j].reader.error("parent",
                             unknown_name_message("\"base\" or a joint", joint.parent, choices));
      continue;
    }
    if (in_reported_cycle.contains(joint.name)) continue;
    // Walk up at most as many links as there are joints: a longer chain repeats a joint.
    std::vector<std::string> chain{joint.name};
    const JointConfig* at = &joint;
    bool cycle = false;
    for (std::size_t step = 0; step <= rig.joints.size(); ++step) {
      if (at->parent == kBase) break;
      at = rig.find_joint(at->parent);
      if (at == nullptr) break;  // Reported at that joint.
      chain.push_back(at->name);
      if (at->name == joint.name) {
        cycle = true;
        break;
      }
      if (std::count(chain.begin(), chain.end(), at->name) > 1) break;  // A cycle above us.
    }
    if (cycle) {
      std::string path;
      for (const auto& link : chain) {
        path += (path.empty() ? "" : " -> ") + link;
        in_reported_cycle.insert(link);
      }
      joints[j].reader.error("parent",
                             "expected a chain of parents ending at \"base\", found a "
                             "cycle: " +
                                 path);
    }
  }
}

void check_stereo(const RigConfig& rig, MapReader& r,
                  const std::vector<std::string>& camera_names) {
  const auto& stereo = *rig.stereo;
  const CameraConfig* left = nullptr;
  const CameraConfig* right = nullptr;
  if (!stereo.left_camera.empty()) {
    left = rig.find_camera(stereo.left_camera);
    if (left == nullptr) {
      r.error("left_camera", unknown_name_message("a camera", stereo.left_camera, camera_names));
    }
  }
  if (!stereo.right_camera.empty()) {
    right = rig.find_camera(stereo.right_camera);
    if (right == nullptr) {
      r.error("right_camera", unknown_name_message("a camera", stereo.right_camera, camera_names));
    }
  }
  if (left != nullptr && left == right) {
    r.error("right_camera", "expected a camera other than left_camera, found " +
                                in_quotes(stereo.right_camera) + " for both");
    return;
  }
  if (left == nullptr || right == nullptr || stereo.baseline_m <= 0.0) return;
  const JointConfig* left_eye = rig.find_joint(left->parent);
  const JointConfig* right_eye = rig.find_joint(right->parent);
  if (left_eye == nullptr || right_eye == nullptr || left_eye == right_eye) return;
  // The eyes pan about parallel axes set apart along y (rigs/cambio.yaml's frame convention).
  const double distance_m = std::abs(left_eye->origin.xyz_m[1] - right_eye->origin.xyz_m[1]);
  if (std::abs(distance_m - stereo.baseline_m) > kBaselineTolerance_m) {
    r.error("baseline_m", "expected " + format_number(distance_m) +
                              " (the distance in y between the origins of joints " +
                              left_eye->name + " and " + right_eye->name + "), found " +
                              format_number(stereo.baseline_m));
  }
}

std::vector<std::string> names_of(const auto& items) {
  std::vector<std::string> names;
  for (const auto& item : items) names.push_back(item.name);
  return names;
}

}  // namespace

std::vector<LoopConfig> default_loops() {
  return {
      LoopConfig{"joint", 1000.0, 0, -1, OverrunPolicy::kSkip, kDefaultCommandTimeout_s,
                 kDefaultFeedbackTimeout_s},
      LoopConfig{"control", 200.0, 0, -1, OverrunPolicy::kSkip},
      LoopConfig{"perception", 60.0, 0, -1, OverrunPolicy::kSkip},
      LoopConfig{"camera", 30.0, 0, -1, OverrunPolicy::kSkip},
  };
}

namespace {

/// The readers of the sections read_rig reads, kept for the checks across sections: each issue
/// they find is located at the entry it is about, once every section was read.
struct SectionReaders {
  std::vector<JointEntry> joints;
  bool too_many_joints = false;
  std::vector<GroupEntry> groups;
  std::vector<MapReader> cameras;
  std::optional<MapReader> stereo;
  std::vector<MapReader> touch_sensors;
  std::vector<MapReader> can_buses;
};

void read_rig_header(MapReader& root, RigConfig& rig) {
  MapReader header = root.map("rig");
  rig.name = header.text("name");
  header.finish();
}

/// Joints are required, and at most kMaxJoints of them (the joint loop's frames hold that many).
void read_joints(MapReader& root, RigConfig& rig, SectionReaders& readers) {
  if (!root.has("joints")) root.error("joints", "missing key (expected a map of joints by name)");
  for (auto& [name, reader] : root.named_maps("joints")) {
    std::optional<MapReader> can;
    rig.joints.push_back(read_joint(name, reader, can));
    readers.joints.push_back(JointEntry{reader, can});
  }
  if (root.has("joints") && rig.joints.empty()) {
    root.error("joints", "expected at least one joint, found none");
  }
  readers.too_many_joints = rig.joints.size() > kMaxJoints;
  if (readers.too_many_joints) {
    root.error("joints", "expected at most " + std::to_string(kMaxJoints) +
                             " joints (the joint loop's frames hold that many), found " +
                             std::to_string(rig.joints.size()));
  }
}

void read_groups(MapReader& root, RigConfig& rig, SectionReaders& readers) {
  if (!root.has("groups"))
    root.error("groups", "missing key (expected a map of joint groups by name)");
  for (auto& [name, reader] : root.named_maps("groups")) {
    rig.groups.push_back(read_group(name, reader));
    readers.groups.push_back(GroupEntry{reader});
  }
  if (root.has("groups") && rig.groups.empty()) {
    root.error("groups", "expected at least one group, found none");
  }
}

/// The cameras' pixels together are bounded too: the sim renders and keeps every camera's
/// frames. The camera that passes the bound is the one reported.
void read_cameras(MapReader& root, RigConfig& rig, SectionReaders& readers) {
  std::int64_t camera_pixels = 0;
  for (auto& [name, reader] : root.named_maps("cameras")) {
    const CleanRead camera_read(reader);
    rig.cameras.push_back(read_camera(name, reader));
    readers.cameras.push_back(reader);
    const CameraConfig& camera = rig.cameras.back();
    camera_pixels += std::int64_t{camera.width_px} * camera.height_px;
    if (camera_read.clean() && camera_pixels > kMaxCameraPixels) {
      reader.error("", "expected the cameras to hold at most " + std::to_string(kMaxCameraPixels) +
                           " pixels together (two of " + std::to_string(kMaxCameraSide_px) + " x " +
                           std::to_string(kMaxCameraSide_px) +
                           ": the sim renders and keeps every camera's frames), found " +
                           std::to_string(camera_pixels) + " with this camera");
    }
  }
}

/// The pair's cameras and baseline are checked against the cameras and joints later
/// (check_stereo), once every section was read.
void read_stereo(MapReader& root, RigConfig& rig, SectionReaders& readers) {
  readers.stereo = root.optional_map("stereo");
  if (readers.stereo) {
    StereoConfig stereo;
    stereo.left_camera = readers.stereo->text("left_camera");
    stereo.right_camera = readers.stereo->text("right_camera");
    stereo.baseline_m = readers.stereo->number("baseline_m", Range::positive());
    readers.stereo->finish();
    rig.stereo = stereo;
  }
}

TouchSensorConfig read_touch_sensor(const std::string& name, MapReader& reader) {
  TouchSensorConfig sensor;
  sensor.name = name;
  sensor.backend = read_backend_name(reader, sensor.backend);
  sensor.backend_at = reader.location_of("backend");
  sensor.parent = reader.text("parent");
  if (reader.has("fingertip_xy_m")) {
    const CleanRead tip_read(reader);
    // Along the finger: a hand's size; off the midline: within half a gripper's span.
    const auto tip = reader.numbers("fingertip_xy_m", Range::closed(0.0, 1.0));
    if (tip_read.clean() && tip.size() != 2) {
      reader.error("fingertip_xy_m", "expected a list of 2 numbers [x, y] in m, found a list of " +
                                         std::to_string(tip.size()));
    } else if (tip_read.clean() && (tip[0] < 0.01 || tip[1] > 0.2)) {
      reader.error("fingertip_xy_m",
                   "expected x in [0.01, 1] m (along the finger) and y in "
                   "[0, 0.2] m (off the gripper's midline)");
    } else if (tip_read.clean()) {
      sensor.fingertip_x_m = tip[0];
      sensor.fingertip_y_m = tip[1];
    }
  }
  reader.finish();
  return sensor;
}

void read_touch_sensors(MapReader& root, RigConfig& rig, SectionReaders& readers) {
  for (auto& [name, reader] : root.named_maps("touch_sensors")) {
    rig.touch_sensors.push_back(read_touch_sensor(name, reader));
    readers.touch_sensors.push_back(reader);
  }
}

void read_can_buses(MapReader& root, RigConfig& rig, SectionReaders& readers) {
  for (auto& [name, reader] : root.named_maps("can_buses")) {
    rig.can_buses.push_back(read_can_bus(name, reader));
    readers.can_buses.push_back(reader);
  }
}

/// The file's loops, then the standard loops it leaves out; a group without a rate of its own
/// runs at the joint loop's.
void read_loops(MapReader& root, RigConfig& rig) {
  for (auto& [name, reader] : root.named_maps("loops"))
    rig.loops.push_back(read_loop(name, reader));
  for (const auto& loop : default_loops()) {
    if (rig.find_loop(loop.name) == nullptr) rig.loops.push_back(loop);
  }
  for (auto& group : rig.groups) {
    if (!group.own_rate) group.rate_hz = rig.find_loop("joint")->rate_hz;
  }
}

void read_sim_section(MapReader& root, RigConfig& rig) {
  if (auto sim = root.optional_map("sim")) {
    rig.sim.physics_rate_hz = sim->number_or(
        "physics_rate_hz", rig.sim.physics_rate_hz,
        Range::closed(kMinPhysicsRate_hz, kMaxRate_hz)
            .because("the encoders' 10 ms velocity window needs a step of at most 10 ms; the "
                     "dead-time lines grow with the rate"));
    // A name or an index, read as text and parsed as CAMBIO_EGL_DEVICE is (text_or reports a
    // value that is not text, and returns "auto" for it).
    const std::string render_device = sim->text_or("render_device", "auto");
    if (const auto device = parse_render_device(render_device)) {
      rig.sim.render_device = *device;
    } else {
      sim->error("render_device", render_device_mismatch(render_device));
    }
    sim->finish();
  }
}

void read_runtime_section(MapReader& root, RigConfig& rig) {
  if (auto runtime = root.optional_map("runtime")) {
    rig.runtime.lock_memory = runtime->boolean_or("lock_memory", false);
    runtime->finish();
  }
}

/// Where each key of the sections was, for the checks a later layer makes (RigConfig::locations).
void record_section_locations(const SectionReaders& readers, RigConfig& rig) {
  for (const auto& joint : readers.joints) {
    joint.reader.record_locations(rig.locations);
    if (joint.can) joint.can->record_locations(rig.locations);
  }
  for (const auto& group : readers.groups) group.reader.record_locations(rig.locations);
  for (const auto& reader : readers.cameras) reader.record_locations(rig.locations);
  for (const auto& reader : readers.touch_sensors) reader.record_locations(rig.locations);
  for (const auto& reader : readers.can_buses) reader.record_locations(rig.locations);
}

/// Cameras hang from "base" or a joint; touch sensors from a joint (a gripper).
void check_sensor_parents(const RigConfig& rig, SectionReaders& readers,
                          const std::vector<std::string>& joint_names) {
  std::vector<std::string> link_names{std::string(kBase)};
  link_names.insert(link_names.end(), joint_names.begin(), joint_names.end());
  for (std::size_t c = 0; c < rig.cameras.size(); ++c) {
    const auto& parent = rig.cameras[c].parent;
    if (!parent.empty() && parent != kBase && rig.find_joint(parent) == nullptr) {
      readers.cameras[c].error("parent",
                               unknown_name_message("\"base\" or a joint", parent, link_names));
    }
  }
  for (std::size_t t = 0; t < rig.touch_sensors.size(); ++t) {
    const auto& parent = rig.touch_sensors[t].parent;
    if (!parent.empty() && rig.find_joint(parent) == nullptr) {
      readers.touch_sensors[t].error("parent",
                                     unknown_name_message("a joint", parent, joint_names));
    }
  }
}

/// Consistency across sections, on what was read. Some checks walk the joints once per joint:
/// with too many joints (already reported) they are skipped, and what was found so far thrown.
void check_consistency(MapReader& root, RigConfig& rig, SectionReaders& readers) {
  if (readers.too_many_joints) root.issues()->throw_if_any();
  const std::vector<std::string> joint_names = names_of(rig.joints);
  check_group_membership(rig, readers.joints, readers.groups, joint_names);
  check_kinematic_tree(rig, readers.joints, joint_names);
  check_sensor_parents(rig, readers, joint_names);
  if (rig.stereo) check_stereo(rig, *readers.stereo, names_of(rig.cameras));
}

}  // namespace

RigConfig read_rig(MapReader root, const std::string& file) {
  RigConfig rig;
  rig.source_file = file;
  SectionReaders readers;
  read_rig_header(root, rig);
  read_joints(root, rig, readers);
  read_groups(root, rig, readers);
  read_cameras(root, rig, readers);
  read_camera_calibration_key(root, rig);
  read_stereo(root, rig, readers);
  read_touch_sensors(root, rig, readers);
  read_can_buses(root, rig, readers);
  read_loops(root, rig);
  read_sim_section(root, rig);
  read_runtime_section(root, rig);
  root.finish();

  record_section_locations(readers, rig);
  check_consistency(root, rig, readers);
  root.issues()->throw_if_any();
  return rig;
}

RigConfig load_rig(const std::string& path, const std::vector<ConfigOverride>& overrides) {
  ConfigDocument document = ConfigDocument::load_file(path, overrides);
  return read_rig(document.root(), document.file());
}

RigConfig load_rig_from_string(const std::string& yaml, const std::string& name,
                               const std::vector<ConfigOverride>& overrides) {
  ConfigDocument document = ConfigDocument::from_string(yaml, name, overrides);
  return read_rig(document.root(), document.file());
}

}  // namespace cambio::config
