// `cambio check-config FILE [--set key.path=value]...`: validate a rig file and summarise it.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "argument_parser.hpp"
#include "builtin_backends.hpp"
#include "cambio/canopen/can_bus_load.hpp"
#include "cambio/canopen/can_rig_from_config.hpp"
#include "cambio/canopen/socketcan_backend.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "can_interface_bitrate.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "rig_backend_check.hpp"

namespace cambio::app {

namespace {

using config::RigConfig;

std::string fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

/// Shortest readable form: 0.12, 554.256, 1000.
std::string plain(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

/// "1 joint", "2 joints".
std::string count(std::size_t n, const std::string& singular, std::string plural = {}) {
  if (plural.empty()) plural = singular + "s";
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

double degrees(double radians) {
  return radians * 180.0 / std::numbers::pi;
}

std::string pad(std::string text, std::size_t width) {
  if (text.size() < width) text.append(width - text.size(), ' ');
  return text;
}

std::string vector_text(const std::array<double, 3>& v, double scale = 1.0) {
  return "[" + plain(v[0] * scale) + ", " + plain(v[1] * scale) + ", " + plain(v[2] * scale) + "]";
}

/// Whether this machine's interface runs at the rig's bit rate (the OS sets it, not the stack).
void print_interface_check(const canopen::CanBusInfo& bus, std::ostream& out) {
  const CanInterfaceBitrate here = query_can_interface_bitrate(bus.interface);
  out << "    ";
  if (!here.present) {
    out << "interface " << bus.interface << " not present here: bit rate not checked\n";
  } else if (!here.bitrate_bit_s) {
    out << "interface "
        << bus.interface << " reports no bit rate here (a virtual CAN interface has none): not checked\n";
  } else if (*here.bitrate_bit_s == bus.bitrate_bit_s) {
    out << "interface " << bus.interface << " runs at " << *here.bitrate_bit_s
        << " bit/s, as the rig says\n";
  } else {
    out << "MISMATCH: interface " << bus.interface << " runs at " << *here.bitrate_bit_s
        << " bit/s, the rig says " << bus.bitrate_bit_s << " (set it: ip link set "
        << bus.interface << " down; ip link set " << bus.interface << " type can bitrate "
        << bus.bitrate_bit_s << "; ip link set " << bus.interface << " up)\n";
  }
}

void print_summary(const RigConfig& rig, const config::RenderDeviceChoice& render_device,
                   std::ostream& out) {
  out << "rig " << rig.name << " (" << rig.source_file << "): OK\n";
  out << "  " << count(rig.joints.size(), "joint") << " in " << count(rig.groups.size(), "group")
      << ", " << count(rig.cameras.size(), "camera") << ", " << count(rig.loops.size(), "loop")
      << ", " << count(rig.can_buses.size(), "CAN bus", "CAN buses") << "\n";

  std::size_t name_width = 0;
  for (const auto& joint : rig.joints) name_width = std::max(name_width, joint.name.size());

  out << "\ngroups\n";
  for (const auto& group : rig.groups) {
    out << "  " << group.name << ": backend " << group.backend << ", joint loop "
        << plain(group.rate_hz) << " Hz" << (group.own_rate ? "" : " (loops.joint)");
    if (!group.can_bus.empty()) out << ", CAN bus " << group.can_bus;
    out << "\n";
    for (const auto& joint_name : group.joints) {
      const auto* joint = rig.find_joint(joint_name);
      if (joint == nullptr) continue;
      const std::string limits = "[" + fixed(degrees(joint->min_position_rad), 1) + ", " +
                                 fixed(degrees(joint->max_position_rad), 1) + "] deg";
      out << "    " << pad(joint->name, name_width) << "  " << pad(limits, 22) << "max "
          << plain(joint->max_velocity_rad_s) << " rad/s, " << plain(joint->max_acceleration_rad_s2)
          << " rad/s^2";
      if (joint->max_effort_nm > 0) out << ", " << plain(joint->max_effort_nm) << " N m";
      out << "  parent " << joint->parent;
      if (joint->can) out << "  node " << joint->can->node_id;
      out << "\n";
    }
  }

  if (!rig.cameras.empty()) {
    out << "\ncameras\n";
    for (const auto& camera : rig.cameras) {
      out << "  " << camera.name << ": " << camera.width_px << "x" << camera.height_px << " "
          << (camera.format == config::PixelFormatConfig::kGrey8 ? "grey8" : "rgb8") << ", focal ";
      if (camera.focal_x_px == camera.focal_y_px) {
        out << plain(camera.focal_x_px) << " px";
      } else {
        out << plain(camera.focal_x_px) << " x " << plain(camera.focal_y_px) << " px";
      }
      out << ", principal point (" << plain(camera.principal_x_px) << ", "
          << plain(camera.principal_y_px) << "), on " << camera.parent << " at "
          << vector_text(camera.mount.xyz_m) << " m, rpy "
          << vector_text(camera.mount.rpy_rad, 180.0 / std::numbers::pi) << " deg ("
          << camera.backend << ")\n";
    }
  }
  if (rig.stereo) {
    out << "  stereo: " << rig.stereo->left_camera << " + " << rig.stereo->right_camera
        << ", baseline " << plain(rig.stereo->baseline_m) << " m\n";
  }
  if (!rig.touch_sensors.empty()) {
    out << "\ntouch sensors\n";
    for (const auto& sensor : rig.touch_sensors) {
      out << "  " << sensor.name << " on " << sensor.parent << "\n";
    }
  }

  out << "\nloops\n";
  for (const auto& loop : rig.loops) {
    out << "  " << pad(loop.name, 12) << pad(plain(loop.rate_hz) + " Hz", 10)
        << (loop.priority > 0 ? "SCHED_FIFO " + std::to_string(loop.priority) : "normal priority")
        << ", cpu " << (loop.cpu < 0 ? "any" : std::to_string(loop.cpu)) << ", overrun "
        << (loop.overrun == config::OverrunPolicy::kCatchUp ? "catch_up" : "skip") << "\n";
  }

  if (!rig.can_buses.empty()) {
    const std::string master = canopen::SocketCanBackend::kName;
    const hal::HardwareInfo hardware = config::hardware_description(rig);
    const canopen::CanRigInfo can_rig = canopen::can_rig_from_config(rig);
    out << "\nCAN buses (worst-case load of the " << master << " groups; the limit is "
        << plain(canopen::kMaxCanBusLoad * 100.0) << "%)\n";
    for (const auto& bus : can_rig.buses) {
      out << "  " << bus.name << ": interface " << bus.interface << ", "
          << plain(static_cast<double>(bus.bitrate_bit_s) / 1000.0) << " kbit/s";
      if (bus.fd) {
        out << ", FD data " << plain(static_cast<double>(bus.data_bitrate_bit_s) / 1000.0)
            << " kbit/s";
      }
      const canopen::CanBusLoad load = canopen::can_bus_load(hardware, can_rig, bus, master);
      if (load.groups.empty()) {
        out << ", no " << master << " groups\n";
      } else {
        out << ", load " << fixed(load.load * 100.0, 1) << "% (" << fixed(load.bit_s, 0)
            << " bit/s)\n";
        for (const auto& group : load.groups) {
          out << "    " << group.group << ": "
              << count(static_cast<std::size_t>(group.drives), "drive") << " at "
              << plain(group.rate_hz) << " Hz, " << group.bits_per_cycle
              << " bits per cycle + heartbeats: " << fixed(group.bit_s, 0) << " bit/s\n";
        }
      }
      print_interface_check(bus, out);
    }
  }
  out << "\nsim physics " << plain(rig.sim.physics_rate_hz) << " Hz, render device "
      << config::to_string(render_device.device);
  if (render_device.from_environment()) {
    out << " (" << config::kRenderDeviceVariable << "; the rig says "
        << config::to_string(rig.sim.render_device) << ")";
  }
  out << "; lock memory " << (rig.runtime.lock_memory ? "yes" : "no") << "\n";
}

}  // namespace

int run_check_config_command(std::span<const std::string> args) {
  ArgumentParser parser("check-config", "FILE [--set key.path=value]...");
  parser.positional("FILE", "rig file to validate, e.g. firmware_config/rigs/cambio.yaml")
      .repeated_option(
          "set", "KEY.PATH=VALUE",
          "override a key before validation; the value is YAML, e.g. "
          "--set loops.joint.rate_hz=500 or --set cameras.left_eye.origin_xyz_m=[0.02,0,0]");
  if (!parser.parse(args)) return kExitOk;

  const auto overrides = parse_overrides_or_report(parser.values("set"));
  if (!overrides) return kExitBadInput;
  const auto rig = load_rig_or_report(*parser.positional_value("FILE"), *overrides);
  if (!rig) return kExitBadInput;
  config::RenderDeviceChoice render_device;
  try {
    // The names of the backends this build carries, from their registrations.
    config::ExperimentConfig names_only;
    names_only.rig = *rig;
    hal::BackendFactory factory;
    register_builtin_backends(factory, names_only);
    check_rig_backends(*rig, factory);
    render_device = config::choose_render_device(rig->sim.render_device, rig->source_file);
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }
  print_summary(*rig, render_device, std::cout);
  return kExitOk;
}

}  // namespace cambio::app
