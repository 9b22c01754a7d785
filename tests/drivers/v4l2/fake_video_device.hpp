#pragma once

// A V4L2 capture device in memory, behaving as the kernel's queues do: the test plays the driver
// (fill() takes the oldest queued buffer, or drops the frame when none is queued, advancing the
// sequence either way), the code under test the application (dequeue never waits).

#include <algorithm>
#include <array>
#include <atomic>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "cambio/v4l2/stamp_mapping.hpp"
#include "cambio/v4l2/video_device.hpp"

namespace cambio::v4l2::test {

/// A fixed-capacity FIFO: the device's queue calls run inside the allocation-counted grab.
template <class T>
class Fifo {
 public:
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  void clear() { head_ = size_ = 0; }
  void push_back(const T& value) {
    items_[(head_ + size_) % items_.size()] = value;
    ++size_;
  }
  const T& front() const { return items_[head_]; }
  void pop_front() {
    head_ = (head_ + 1) % items_.size();
    --size_;
  }

 private:
  std::array<T, 16> items_{};
  std::size_t head_ = 0;
  std::size_t size_ = 0;
};

class FakeVideoDevice final : public VideoDevice {
 public:
  struct Control {
    ControlRange range;
    std::int32_t value = 0;
  };

  explicit FakeVideoDevice(DeviceModes modes, std::string path = "/dev/video0")
      : path_(std::move(path)), modes_(std::move(modes)) {}

  const std::string& path() const override { return path_; }
  DeviceModes modes() override { return modes_; }
  StreamFormat set_format(std::uint32_t code, int width_px, int height_px) override {
    const std::size_t per_pixel = code == kFourccYuyv ? 2 : 1;
    format_ = {code, width_px, height_px,
               static_cast<std::size_t>(width_px) * per_pixel + row_padding_bytes, 0};
    format_.size_bytes = format_.bytes_per_line * static_cast<std::size_t>(height_px);
    if (code == kFourccMjpeg) {
      // Compressed: no rows; a buffer as large as drivers make one (room for a poor ratio).
      format_.bytes_per_line = 0;
      format_.size_bytes = static_cast<std::size_t>(width_px) * height_px * 3 + 4096;
    }
    return format_;
  }
  FrameInterval set_frame_interval(FrameInterval interval) override {
    interval_ = interval;
    return interval;
  }
  std::optional<ControlRange> query_control(std::uint32_t id) override {
    const auto it = controls.find(id);
    if (it == controls.end()) return std::nullopt;
    return it->second.range;
  }
  void set_control(std::uint32_t id, std::int32_t value) override {
    controls.at(id).value =
        std::clamp(value, controls.at(id).range.minimum, controls.at(id).range.maximum);
  }
  std::int32_t control(std::uint32_t id) override { return controls.at(id).value; }
  std::size_t map_buffers(std::size_t count) override {
    free_running_frame_.assign(format_.size_bytes, 0);
    buffers_.assign(std::min(count, max_buffers), std::vector<std::uint8_t>(format_.size_bytes));
    return buffers_.size();
  }
  void start_streaming() override {
    queued_.clear();
    done_.clear();
    for (std::uint32_t i = 0; i < buffers_.size(); ++i) queued_.push_back(i);
    streaming = true;
  }
  void stop_streaming() noexcept override { streaming = false; }

  StreamResult dequeue(FilledBuffer& out) noexcept override {
    if (gone) return StreamResult::kGone;
    // A free-running camera: the frames due by now (CLOCK_MONOTONIC) arrive, each stamped when
    // it was due, holding its frame count.
    if (free_running_period_ns > 0 && streaming) {
      const std::int64_t now_ns = monotonic_now_ns();
      if (next_frame_ns_ == 0) next_frame_ns_ = now_ns;
      for (; next_frame_ns_ <= now_ns; next_frame_ns_ += free_running_period_ns) {
        std::fill(free_running_frame_.begin(), free_running_frame_.end(),
                  static_cast<std::uint8_t>(next_sequence_));
        (void)fill(next_frame_ns_, free_running_frame_);
      }
    }
    if (done_.empty()) return StreamResult::kNotReady;
    out = done_.front();
    done_.pop_front();
    return StreamResult::kOk;
  }
  StreamResult requeue(std::uint32_t index) noexcept override {
    if (gone) return StreamResult::kGone;
    queued_.push_back(index);
    return StreamResult::kOk;
  }
  std::span<const std::uint8_t> buffer(std::uint32_t index) const noexcept override {
    if (index >= buffers_.size()) return {};
    return buffers_[index];
  }

  /// The driver captures a frame stamped `stamp_ns` (CLOCK_MONOTONIC) holding `bytes`; false
  /// when no buffer was queued (the frame is lost, as the kernel loses it).
  bool fill(std::int64_t stamp_ns, const std::vector<std::uint8_t>& bytes, bool monotonic = true) {
    const std::uint32_t sequence = next_sequence_++;
    if (queued_.empty()) return false;
    const std::uint32_t index = queued_.front();
    queued_.pop_front();
    std::copy(bytes.begin(), bytes.end(), buffers_[index].begin());
    done_.push_back({index, bytes.size(), sequence, stamp_ns, monotonic, false});
    return true;
  }
  std::size_t queued() const { return queued_.size(); }
  const StreamFormat& format() const { return format_; }
  const FrameInterval& interval() const { return interval_; }

  std::map<std::uint32_t, Control> controls;
  std::size_t max_buffers = 8;        ///< At most 16 (the FIFOs' capacity).
  std::size_t row_padding_bytes = 0;  ///< Extra bytes per row, as drivers align lines.
  std::atomic<bool> gone{false};      ///< Unplugged: every streaming call says ENODEV.
  bool streaming = false;
  /// > 0: frames arrive by themselves at this period (monotonic time), as from a real camera.
  std::int64_t free_running_period_ns = 0;

 private:
  std::string path_;
  DeviceModes modes_;
  StreamFormat format_;
  FrameInterval interval_;
  std::vector<std::vector<std::uint8_t>> buffers_;
  Fifo<std::uint32_t> queued_;
  Fifo<FilledBuffer> done_;
  std::uint32_t next_sequence_ = 0;
  std::int64_t next_frame_ns_ = 0;
  std::vector<std::uint8_t> free_running_frame_;
};

}  // namespace cambio::v4l2::test
