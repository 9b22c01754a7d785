#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

#include "cambio/v4l2/device_modes.hpp"

namespace cambio::v4l2 {

/// A device call that failed while configuring: the message names the device, the call and the
/// kernel's reason.
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The format the driver set (VIDIOC_S_FMT answers with what it chose, which may differ).
struct StreamFormat {
  std::uint32_t fourcc = 0;
  int width_px = 0;
  int height_px = 0;
  std::size_t bytes_per_line = 0;
  std::size_t size_bytes = 0;
};

/// An integer control's range (VIDIOC_QUERYCTRL).
struct ControlRange {
  std::int32_t minimum = 0;
  std::int32_t maximum = 0;
  std::int32_t step = 1;
};

/// A filled buffer taken from the driver's outgoing queue.
struct FilledBuffer {
  std::uint32_t index = 0;
  std::size_t bytes_used = 0;
  std::uint32_t sequence = 0;  ///< The driver's frame counter: a gap is frames it dropped.
  std::int64_t stamp_ns = 0;   ///< The driver's stamp, CLOCK_MONOTONIC when `monotonic`.
  bool monotonic = false;      ///< V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC was set.
  bool corrupted = false;      ///< V4L2_BUF_FLAG_ERROR: the frame may be damaged.
};

/// What a streaming call met.
enum class StreamResult : std::uint8_t {
  kOk,
  kNotReady,  ///< No filled buffer yet (EAGAIN): "no new frame", never a wait.
  kGone,      ///< The device was unplugged (ENODEV): a camera fault.
  kFailed,    ///< Any other error.
};

/// One V4L2 capture device, as thin as the ioctls it stands for, so the camera's logic is tested
/// without a kernel (a fake in the tests, KernelVideoDevice on Linux). Configure-time calls may
/// allocate and throw DeviceError; the streaming calls (dequeue, requeue, buffer) are
/// real-time safe, noexcept and never block.
class VideoDevice {
 public:
  virtual ~VideoDevice() = default;

  /// The device node, for messages.
  virtual const std::string& path() const = 0;
  /// Every format, size and rate the device offers (VIDIOC_ENUM_FMT, ENUM_FRAMESIZES,
  /// ENUM_FRAMEINTERVALS); a format whose sizes the driver does not enumerate lists its current
  /// size alone.
  virtual DeviceModes modes() = 0;
  virtual StreamFormat set_format(std::uint32_t fourcc, int width_px, int height_px) = 0;
  /// Asks for `interval` (VIDIOC_S_PARM) and returns what the driver set.
  virtual FrameInterval set_frame_interval(FrameInterval interval) = 0;
  /// nullopt when the device has no control `id` (a V4L2_CID_*).
  virtual std::optional<ControlRange> query_control(std::uint32_t id) = 0;
  virtual void set_control(std::uint32_t id, std::int32_t value) = 0;
  virtual std::int32_t control(std::uint32_t id) = 0;
  /// Requests and maps `count` buffers (VIDIOC_REQBUFS, QUERYBUF, mmap); returns how many the
  /// driver granted (at least 2, else DeviceError).
  virtual std::size_t map_buffers(std::size_t count) = 0;
  /// Queues every buffer and starts streaming.
  virtual void start_streaming() = 0;
  /// Stops streaming; every buffer returns to the application. noexcept, idempotent.
  virtual void stop_streaming() noexcept = 0;

  virtual StreamResult dequeue(FilledBuffer& out) noexcept = 0;
  virtual StreamResult requeue(std::uint32_t index) noexcept = 0;
  /// A mapped buffer's bytes (empty for an index out of range).
  virtual std::span<const std::uint8_t> buffer(std::uint32_t index) const noexcept = 0;
};

}  // namespace cambio::v4l2
