#include "cambio/v4l2/v4l2_rig_check.hpp"

#include <map>
#include <string>

#include "cambio/v4l2/v4l2_backend.hpp"

namespace cambio::v4l2 {

namespace {

std::string in_quotes(std::string_view text) {
  return "'" + std::string(text) + "'";
}

// A device node is a plain path under /dev/: nothing the rig names may walk out of it.
bool is_device_node(const std::string& path) {
  return path.rfind("/dev/", 0) == 0 && path.size() > 5 && path.find("/../") == std::string::npos &&
         path.find("/./") == std::string::npos && path.back() != '/' &&
         path.compare(path.size() - 3, 3, "/..") != 0;
}

}  // namespace

std::vector<hal::SettingProblem> check_v4l2_rig(const hal::HardwareInfo& hardware,
                                                const V4l2RigInfo& rig) {
  std::vector<hal::SettingProblem> problems;
  std::map<std::string, std::string> device_users;
  for (const hal::CameraInfo& camera : hardware.cameras) {
    const std::string key = "cameras." + camera.name + ".";
    const V4l2CameraSettings* settings = rig.find(camera.name);
    if (camera.backend != V4l2Backend::kName) {
      if (settings != nullptr && settings->any()) {
        problems.push_back({key + (settings->device.empty() ? "pixel_format" : "device"),
                            "expected no V4L2 settings (device, pixel_format, frame_rate_hz, "
                            "controls) on a camera whose backend is " +
                                in_quotes(camera.backend) + "; they are read with backend: v4l2"});
      }
      continue;
    }
    const V4l2CameraSettings empty;
    const V4l2CameraSettings& given = settings != nullptr ? *settings : empty;
    if (given.device.empty()) {
      problems.push_back({key + "device",
                          "expected the camera's device node (e.g. device: "
                          "/dev/video0) for backend v4l2, found none"});
    } else if (!is_device_node(given.device)) {
      problems.push_back({key + "device",
                          "expected a device node under /dev/ (e.g. "
                          "/dev/video0 or /dev/v4l/by-id/...), found " +
                              in_quotes(given.device)});
    } else if (const auto [user, inserted] = device_users.emplace(given.device, camera.name);
               !inserted) {
      problems.push_back({key + "device", "expected a device of its own, found " +
                                              in_quotes(given.device) + ", which camera " +
                                              in_quotes(user->second) + " already streams from"});
    }
    if (given.pixel_format.empty()) {
      problems.push_back(
          {key + "pixel_format",
           "expected the device's pixel format (GREY, YUYV or MJPG) for backend v4l2, "
           "found none"});
    } else if (given.pixel_format != "GREY" && given.pixel_format != "YUYV" &&
               given.pixel_format != "MJPG") {
      problems.push_back({key + "pixel_format",
                          "expected GREY, YUYV or MJPG (the formats this build reads), found " +
                              in_quotes(given.pixel_format)});
    } else if (given.pixel_format == "YUYV" && camera.intrinsics.width_px % 2 != 0) {
      problems.push_back({key + "width_px",
                          "expected an even width for YUYV (two pixels share "
                          "their colour), found " +
                              std::to_string(camera.intrinsics.width_px)});
    }
    if (!(given.frame_rate_hz > 0.0)) {
      problems.push_back({key + "frame_rate_hz",
                          "expected the rate to stream at (frame_rate_hz) for backend v4l2, "
                          "found none"});
    }
  }
  // Found here, before anything opens: the factory knows "v4l2" as a backend, not that it makes
  // cameras only.
  for (const hal::JointGroupInfo& group : hardware.groups) {
    if (group.backend == V4l2Backend::kName) {
      problems.push_back({"groups." + group.name + ".backend",
                          "expected a backend with joints (e.g. sim or socketcan), found "
                          "'v4l2', which makes cameras only"});
    }
  }
  for (const hal::TouchSensorInfo& sensor : hardware.touch_sensors) {
    if (sensor.backend == V4l2Backend::kName) {
      problems.push_back({"touch_sensors." + sensor.name + ".backend",
                          "expected a backend with touch sensors (e.g. sim), found 'v4l2', "
                          "which makes cameras only"});
    }
  }
  if (hardware.stereo) {
    const hal::CameraInfo* left = hardware.find_camera(hardware.stereo->left_camera);
    const hal::CameraInfo* right = hardware.find_camera(hardware.stereo->right_camera);
    const V4l2CameraSettings* left_settings = rig.find(hardware.stereo->left_camera);
    const V4l2CameraSettings* right_settings = rig.find(hardware.stereo->right_camera);
    if (left != nullptr && right != nullptr && left_settings != nullptr &&
        right_settings != nullptr && left->backend == V4l2Backend::kName &&
        right->backend == V4l2Backend::kName && left_settings->frame_rate_hz > 0.0 &&
        right_settings->frame_rate_hz > 0.0 &&
        left_settings->frame_rate_hz != right_settings->frame_rate_hz) {
      problems.push_back({"cameras." + right->name + ".frame_rate_hz",
                          "expected the stereo pair's cameras at one rate (they pair by "
                          "timestamp), found " +
                              std::to_string(left_settings->frame_rate_hz) + " Hz left and " +
                              std::to_string(right_settings->frame_rate_hz) + " Hz right"});
    }
  }
  return problems;
}

}  // namespace cambio::v4l2
