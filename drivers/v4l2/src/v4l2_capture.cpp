#include "cambio/v4l2/v4l2_capture.hpp"

#include <linux/videodev2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "cambio/v4l2/mode_negotiation.hpp"
#include "cambio/v4l2/pixel_conversion.hpp"

namespace cambio::v4l2 {

namespace {

// V4L2_CID_EXPOSURE_ABSOLUTE counts 100 us units.
constexpr double kExposureUnit_us = 100.0;

std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

}  // namespace

V4l2Capture::V4l2Capture(const hal::CameraInfo& info, V4l2CameraSettings settings,
                         std::unique_ptr<VideoDevice> device, hal::Clock& clock)
    : info_(info), settings_(std::move(settings)), device_(std::move(device)), clock_(clock) {
  if (device_ == nullptr) {
    throw std::invalid_argument("v4l2: camera '" + info_.name + "': no device");
  }
}

void V4l2Capture::configure() {
  const std::string where = "v4l2: camera '" + info_.name + "' on " + device_->path();
  const std::uint32_t code = settings_.pixel_format.size() == 4
                                 ? fourcc(settings_.pixel_format[0], settings_.pixel_format[1],
                                          settings_.pixel_format[2], settings_.pixel_format[3])
                                 : 0;
  if (code != kFourccMjpeg && !can_convert(code, info_.format)) {
    throw std::runtime_error(where + ": cannot convert pixel format '" + settings_.pixel_format +
                             "' (GREY and YUYV are converted, MJPG decoded)");
  }
  const StreamRequest request{code, info_.intrinsics.width_px, info_.intrinsics.height_px,
                              settings_.frame_rate_hz};
  try {
    const FrameInterval asked = negotiate_mode(device_->modes(), request, device_->path());
    stream_.format = device_->set_format(code, request.width_px, request.height_px);
    if (stream_.format.fourcc != code || stream_.format.width_px != request.width_px ||
        stream_.format.height_px != request.height_px) {
      throw ModeRefused(device_->path() + ": asked for " + fourcc_text(code) + " " +
                        std::to_string(request.width_px) + "x" + std::to_string(request.height_px) +
                        ", the driver set " + fourcc_text(stream_.format.fourcc) + " " +
                        std::to_string(stream_.format.width_px) + "x" +
                        std::to_string(stream_.format.height_px));
    }
    stream_.interval = device_->set_frame_interval(asked);
  } catch (const ModeRefused& error) {
    throw ModeRefused("v4l2: camera '" + info_.name + "': " + error.what());
  } catch (const DeviceError& error) {
    throw DeviceError("v4l2: camera '" + info_.name + "': " + error.what());
  }
  // A driver that cannot set its rate (an HDMI input follows its signal) runs at the rig's.
  const double rate_hz =
      stream_.interval.rate_hz() > 0.0 ? stream_.interval.rate_hz() : settings_.frame_rate_hz;
  frame_period_ns_ = static_cast<std::int64_t>(std::llround(1e9 / rate_hz));
  set_controls();
  if (code == kFourccMjpeg) mjpeg_ = std::make_unique<MjpegDecoder>();
  const std::size_t granted =
      device_->map_buffers(static_cast<std::size_t>(settings_.buffer_count));
  // At least one buffer stays queued with the driver, or it stops filling.
  held_capacity_ = std::clamp<std::size_t>(granted - 1, 1, kMaxHeld);
}

void V4l2Capture::set_controls() {
  const std::string where = "v4l2: camera '" + info_.name + "' on " + device_->path() + ": ";
  const auto set = [&](std::uint32_t id, std::uint32_t auto_id, std::int32_t auto_off,
                       std::int32_t value, const char* name) {
    const auto range = device_->query_control(id);
    if (!range) throw std::runtime_error(where + "the device has no " + name + " control");
    if (value < range->minimum || value > range->maximum) {
      throw std::runtime_error(where + name + " " + std::to_string(value) +
                               " is outside the device's range [" + std::to_string(range->minimum) +
                               ", " + std::to_string(range->maximum) + "]");
    }
    // The automatic mode would override the value: switch it off where the device has one.
    if (auto_id != 0 && device_->query_control(auto_id)) device_->set_control(auto_id, auto_off);
    device_->set_control(id, value);
    return device_->control(id);
  };
  const V4l2Controls& controls = settings_.controls;
  if (controls.exposure_us) {
    const auto units =
        static_cast<std::int32_t>(std::lround(*controls.exposure_us / kExposureUnit_us));
    stream_.exposure_us =
        kExposureUnit_us * set(V4L2_CID_EXPOSURE_ABSOLUTE, V4L2_CID_EXPOSURE_AUTO,
                               V4L2_EXPOSURE_MANUAL, units, "exposure (exposure_time_absolute)");
  }
  if (controls.gain) {
    stream_.gain = set(V4L2_CID_GAIN, V4L2_CID_AUTOGAIN, 0, *controls.gain, "gain");
  }
  if (controls.white_balance_k) {
    stream_.white_balance_k = set(V4L2_CID_WHITE_BALANCE_TEMPERATURE, V4L2_CID_AUTO_WHITE_BALANCE,
                                  0, *controls.white_balance_k, "white balance temperature");
  }
}

void V4l2Capture::activate(const StampMapping& mapping) {
  mapping_ = mapping;
  device_->start_streaming();
  streaming_ = true;
}

void V4l2Capture::deactivate() noexcept {
  if (!streaming_) return;
  device_->stop_streaming();
  streaming_ = false;
  held_count_ = 0;
}

hal::Status V4l2Capture::fail(StreamResult result) noexcept {
  StreamResult expected = StreamResult::kOk;
  fault_.compare_exchange_strong(expected, result, std::memory_order_acq_rel);
  return hal::Status::kFault;
}

void V4l2Capture::drop_oldest() noexcept {
  if (held_count_ == 0) return;
  if (const StreamResult result = device_->requeue(held_[0].index); result != StreamResult::kOk) {
    (void)fail(result);
  }
  counters_.dropped.fetch_add(1, std::memory_order_relaxed);
  for (std::size_t k = 1; k < held_count_; ++k) {
    held_[k - 1] = held_[k];
    held_stamps_ns_[k - 1] = held_stamps_ns_[k];
  }
  --held_count_;
}

hal::Status V4l2Capture::poll() noexcept {
  if (faulted()) return hal::Status::kFault;
  if (!streaming_) return hal::Status::kRejected;
  FilledBuffer buffer;
  for (;;) {
    const StreamResult result = device_->dequeue(buffer);
    if (result == StreamResult::kNotReady) break;
    if (result != StreamResult::kOk) return fail(result);
    if (have_sequence_ && buffer.sequence > last_sequence_ + 1) {
      counters_.dropped.fetch_add(buffer.sequence - last_sequence_ - 1, std::memory_order_relaxed);
    }
    have_sequence_ = true;
    last_sequence_ = buffer.sequence;
    if (buffer.corrupted) {
      counters_.dropped.fetch_add(1, std::memory_order_relaxed);
      if (const StreamResult requeued = device_->requeue(buffer.index);
          requeued != StreamResult::kOk) {
        return fail(requeued);
      }
      continue;
    }
    if (held_count_ == held_capacity_) drop_oldest();
    held_[held_count_] = buffer;
    // A driver without monotonic stamps (V4L2_BUF_FLAG_TIMESTAMP_COPY or unknown) is stamped
    // on arrival: later than the exposure by up to the poll period, never on another clock.
    held_stamps_ns_[held_count_] =
        buffer.monotonic ? mapping_.to_run_ns(buffer.stamp_ns) : clock_.now_ns();
    ++held_count_;
  }
  return faulted() ? hal::Status::kFault : hal::Status::kOk;
}

hal::Status V4l2Capture::deliver(std::size_t held_index, hal::Image& out) noexcept {
  if (held_index >= held_count_) return hal::Status::kRejected;
  const FilledBuffer& buffer = held_[held_index];
  const std::span<const std::uint8_t> mapped = device_->buffer(buffer.index);
  const std::span<const std::uint8_t> bytes =
      mapped.first(std::min(buffer.bytes_used, mapped.size()));
  const hal::Status converted =
      mjpeg_ != nullptr
          ? mjpeg_->decode(bytes, out)
          : convert_frame(stream_.format.fourcc, bytes, stream_.format.bytes_per_line, out);
  const std::int64_t stamp_ns = held_stamps_ns_[held_index];
  // Requeue the delivered frame and every older one: newest wins, the older are dropped.
  for (std::size_t k = 0; k < held_index; ++k) drop_oldest();
  if (const StreamResult result = device_->requeue(held_[0].index); result != StreamResult::kOk) {
    (void)fail(result);
  }
  for (std::size_t k = 1; k < held_count_; ++k) {
    held_[k - 1] = held_[k];
    held_stamps_ns_[k - 1] = held_stamps_ns_[k];
  }
  --held_count_;
  if (converted != hal::Status::kOk) {
    counters_.dropped.fetch_add(1, std::memory_order_relaxed);
    return converted;
  }
  out.stamp_ns = stamp_ns;
  out.sequence = next_image_sequence_++;
  counters_.delivered.fetch_add(1, std::memory_order_relaxed);
  if (clock_.now_ns() - stamp_ns > frame_period_ns_) {
    counters_.late.fetch_add(1, std::memory_order_relaxed);
  }
  return faulted() ? hal::Status::kFault : hal::Status::kOk;
}

hal::Status V4l2Capture::grab_newest(hal::Image& out) noexcept {
  const hal::Status polled = poll();
  if (polled != hal::Status::kOk) return polled;
  if (held_count_ == 0) return hal::Status::kNoNewData;
  return deliver(held_count_ - 1, out);
}

std::string V4l2Capture::describe() const {
  std::string text = "v4l2: camera '" + info_.name + "' on " + device_->path() + ": " +
                     fourcc_text(stream_.format.fourcc) + " " +
                     std::to_string(stream_.format.width_px) + "x" +
                     std::to_string(stream_.format.height_px) + " at " +
                     number_text(1e9 / static_cast<double>(frame_period_ns_)) + " Hz";
  if (stream_.exposure_us) text += ", exposure " + number_text(*stream_.exposure_us) + " us";
  if (stream_.gain) text += ", gain " + std::to_string(*stream_.gain);
  if (stream_.white_balance_k) {
    text += ", white balance " + std::to_string(*stream_.white_balance_k) + " K";
  }
  return text;
}

std::string V4l2Capture::fault_message() const {
  switch (fault_.load(std::memory_order_acquire)) {
    case StreamResult::kOk:
    case StreamResult::kNotReady:
      return {};
    case StreamResult::kGone:
      return "v4l2: camera '" + info_.name + "' on " + device_->path() +
             " was unplugged (ENODEV): camera fault";
    case StreamResult::kFailed:
      break;
  }
  return "v4l2: camera '" + info_.name + "' on " + device_->path() +
         " failed while streaming: camera fault";
}

}  // namespace cambio::v4l2
