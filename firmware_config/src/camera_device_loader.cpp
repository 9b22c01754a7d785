#include "cambio/config/camera_device_config.hpp"

namespace cambio::config {

CameraDeviceConfig read_camera_device(MapReader& camera) {
  CameraDeviceConfig device;
  device.device = camera.text_or("device", "");
  device.pixel_format = camera.text_or("pixel_format", "");
  // V4L2 names a format by four characters (a fourcc), padded with spaces when shorter.
  if (!device.pixel_format.empty() &&
      (device.pixel_format.size() > 4 || device.pixel_format.find('/') != std::string::npos)) {
    camera.error("pixel_format",
                 "expected a V4L2 pixel format of up to 4 characters (GREY, "
                 "YUYV), found '" +
                     device.pixel_format + "'");
  }
  device.frame_rate_hz = camera.number_or(
      "frame_rate_hz", 0.0,
      Range{0.0, 1000.0, true, false}.because("the camera loop polls at most at 1 kHz"));
  device.buffer_count = static_cast<int>(camera.integer_or(
      "buffer_count", 4,
      Range::closed(2, 16).because("two buffers stream; more than 16 only add latency")));
  if (auto controls = camera.optional_map("controls")) {
    // Each key is read whether present or not, so that finish()'s "did you mean" knows them all.
    const double exposure_us = controls->number_or(
        "exposure_us", 0.0,
        Range{0.0, 10e6, true, false}.because("V4L2 counts exposure in 100 us"));
    if (controls->has("exposure_us")) device.exposure_us = exposure_us;
    const std::int64_t gain = controls->integer_or("gain", 0, Range::closed(0, 1 << 20));
    if (controls->has("gain")) device.gain = gain;
    const std::int64_t white_balance_k = controls->integer_or(
        "white_balance_k", 0, Range::closed(1000, 20000).because("colour temperatures of light"));
    if (controls->has("white_balance_k")) device.white_balance_k = white_balance_k;
    controls->finish();
  }
  return device;
}

}  // namespace cambio::config
