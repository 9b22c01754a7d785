#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cambio::v4l2 {

/// Image controls the rig sets (V4L2 user and camera controls); absent ones keep the device's
/// own setting. Setting one turns its automatic mode off.
struct V4l2Controls {
  std::optional<double> exposure_us;            ///< V4L2_CID_EXPOSURE_ABSOLUTE, in 100 us.
  std::optional<std::int32_t> gain;             ///< V4L2_CID_GAIN, the device's own units.
  std::optional<std::int32_t> white_balance_k;  ///< V4L2_CID_WHITE_BALANCE_TEMPERATURE.
  bool any() const { return exposure_us || gain || white_balance_k; }
};

/// What the rig's entry of one camera asks of its V4L2 device (the size and the output format
/// are the camera's, hal::CameraInfo).
struct V4l2CameraSettings {
  std::string camera;          ///< The rig's camera name.
  std::string device;          ///< e.g. "/dev/video0"; empty when the entry names none.
  std::string pixel_format;    ///< As V4L2 spells it: "GREY", "YUYV"; empty when not given.
  double frame_rate_hz = 0.0;  ///< 0 when not given.
  int buffer_count = 4;        ///< The mmap ring.
  V4l2Controls controls;
  /// Whether the entry gives any of the settings above (a sim camera must give none).
  bool any() const {
    return !device.empty() || !pixel_format.empty() || frame_rate_hz > 0.0 || controls.any();
  }
};

/// Every camera entry's V4L2 settings, as the config layer read them
/// (drivers/v4l2/config/v4l2_rig_from_config).
struct V4l2RigInfo {
  std::vector<V4l2CameraSettings> cameras;
  const V4l2CameraSettings* find(std::string_view camera_name) const {
    for (const auto& camera : cameras) {
      if (camera.camera == camera_name) return &camera;
    }
    return nullptr;
  }
};

}  // namespace cambio::v4l2
