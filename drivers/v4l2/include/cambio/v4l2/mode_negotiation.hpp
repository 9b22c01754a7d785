#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "cambio/v4l2/device_modes.hpp"

namespace cambio::v4l2 {

/// What the rig asks of a device.
struct StreamRequest {
  std::uint32_t fourcc = 0;
  int width_px = 0;
  int height_px = 0;
  double frame_rate_hz = 0.0;
};

/// A format, size or rate the device does not offer; the message lists what it does offer.
class ModeRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The interval to ask for: the offered one whose rate is within 1% of the request (29.97 Hz
/// answers 30 Hz), or the exact request when the size offers no list of rates. Throws
/// ModeRefused naming `device` and listing, for the format or size that failed, what is offered.
FrameInterval negotiate_mode(const DeviceModes& modes, const StreamRequest& request,
                             std::string_view device);

/// Every format with its sizes and rates, one format per line:
/// "YUYV: 640x480 (30, 15 Hz), 1280x720 (30 Hz)".
std::string describe_modes(const DeviceModes& modes);

}  // namespace cambio::v4l2
