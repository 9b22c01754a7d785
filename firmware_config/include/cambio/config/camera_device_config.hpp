#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "cambio/config/map_reader.hpp"

namespace cambio::config {

/// A real camera's device and what to ask of it: the camera entry's keys
///
///     device: /dev/video0        # the V4L2 node (or /dev/v4l/by-id/...)
///     pixel_format: YUYV         # as the device names it (v4l2-ctl --list-formats)
///     frame_rate_hz: 30
///     buffer_count: 4            # the mmap ring
///     controls: {exposure_us: 10000, gain: 16, white_balance_k: 4600}
///
/// read for every camera; which backend reads them, and what it accepts, is that backend's
/// check (the v4l2 backend refuses them on a sim camera).
struct CameraDeviceConfig {
  std::string device;          ///< Empty when not given.
  std::string pixel_format;    ///< Empty when not given.
  double frame_rate_hz = 0.0;  ///< 0 when not given.
  int buffer_count = 4;
  std::optional<double> exposure_us;
  std::optional<std::int64_t> gain;
  std::optional<std::int64_t> white_balance_k;
};

/// Reads the keys above from a camera entry (before its finish()).
CameraDeviceConfig read_camera_device(MapReader& camera);

}  // namespace cambio::config
