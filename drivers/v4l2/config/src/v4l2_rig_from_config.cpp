#include "cambio/v4l2/v4l2_rig_from_config.hpp"

namespace cambio::v4l2 {

V4l2RigInfo v4l2_rig_from_config(const config::RigConfig& rig) {
  V4l2RigInfo info;
  for (const config::CameraConfig& camera : rig.cameras) {
    const config::CameraDeviceConfig& device = camera.device;
    V4l2CameraSettings settings;
    settings.camera = camera.name;
    settings.device = device.device;
    settings.pixel_format = device.pixel_format;
    settings.frame_rate_hz = device.frame_rate_hz;
    settings.buffer_count = device.buffer_count;
    settings.controls.exposure_us = device.exposure_us;
    if (device.gain) settings.controls.gain = static_cast<std::int32_t>(*device.gain);
    if (device.white_balance_k) {
      settings.controls.white_balance_k = static_cast<std::int32_t>(*device.white_balance_k);
    }
    info.cameras.push_back(std::move(settings));
  }
  return info;
}

}  // namespace cambio::v4l2
