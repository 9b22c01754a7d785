#include "cambio/v4l2/mode_negotiation.hpp"

#include <cmath>
#include <cstdio>

namespace cambio::v4l2 {

namespace {

// A device's 29.97 Hz (1001/30000 s) answers a rig's 30 Hz; 1% keeps 25 and 24 Hz apart.
constexpr double kRateTolerance = 0.01;

std::string rate_text(double rate_hz) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", rate_hz);
  return text;
}

std::string size_text(const FrameSizeOffer& size) {
  std::string text = std::to_string(size.min_width_px) + "x" + std::to_string(size.min_height_px);
  if (!size.is_discrete()) {
    text += " to " + std::to_string(size.max_width_px) + "x" + std::to_string(size.max_height_px) +
            " in steps of " + std::to_string(size.step_width_px) + "x" +
            std::to_string(size.step_height_px);
  }
  if (!size.intervals.empty()) {
    text += " (";
    for (std::size_t k = 0; k < size.intervals.size(); ++k) {
      text += (k == 0 ? "" : ", ") + rate_text(size.intervals[k].rate_hz());
    }
    text += " Hz)";
  }
  return text;
}

std::string sizes_text(const FormatOffer& format) {
  std::string text;
  for (const auto& size : format.sizes) text += (text.empty() ? "" : ", ") + size_text(size);
  return text.empty() ? "no size listed" : text;
}

std::string formats_text(const DeviceModes& modes) {
  std::string text;
  for (const auto& format : modes) {
    text += (text.empty() ? "" : ", ") + fourcc_text(format.fourcc);
  }
  return text.empty() ? "none" : text;
}

}  // namespace

std::string describe_modes(const DeviceModes& modes) {
  std::string text;
  for (const auto& format : modes) {
    text += (text.empty() ? "" : "\n") + fourcc_text(format.fourcc) + ": " + sizes_text(format);
  }
  return text;
}

FrameInterval negotiate_mode(const DeviceModes& modes, const StreamRequest& request,
                             std::string_view device) {
  const std::string where = std::string(device) + ": ";
  const FormatOffer* format = nullptr;
  for (const auto& offer : modes) {
    if (offer.fourcc == request.fourcc) format = &offer;
  }
  if (format == nullptr) {
    throw ModeRefused(where + "pixel format " + fourcc_text(request.fourcc) +
                      " is not offered; the device offers " + formats_text(modes));
  }
  const FrameSizeOffer* size = nullptr;
  for (const auto& offer : format->sizes) {
    if (offer.contains(request.width_px, request.height_px)) size = &offer;
  }
  const std::string asked_size =
      std::to_string(request.width_px) + "x" + std::to_string(request.height_px);
  if (size == nullptr) {
    throw ModeRefused(where + fourcc_text(request.fourcc) + " at " + asked_size +
                      " is not offered; the device offers " + fourcc_text(request.fourcc) + " at " +
                      sizes_text(*format));
  }
  if (size->intervals.empty()) {
    // The driver lists no rates at this size (an HDMI input's rate is its signal's): ask for the
    // request and let the caller read back what the driver set.
    // Rates to a mHz are exact: 60 Hz is 1000/60000 s, 29.97 Hz 1000/29970 s.
    return FrameInterval{1000,
                         static_cast<std::uint32_t>(std::lround(request.frame_rate_hz * 1e3))};
  }
  for (const auto& interval : size->intervals) {
    const double rate_hz = interval.rate_hz();
    if (std::abs(rate_hz - request.frame_rate_hz) <= kRateTolerance * request.frame_rate_hz) {
      return interval;
    }
  }
  throw ModeRefused(where + fourcc_text(request.fourcc) + " " + asked_size + " at " +
                    rate_text(request.frame_rate_hz) + " Hz is not offered; the device offers " +
                    size_text(*size));
}

}  // namespace cambio::v4l2
