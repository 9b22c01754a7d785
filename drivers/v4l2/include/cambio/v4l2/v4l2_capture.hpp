#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "cambio/hal/camera.hpp"
#include "cambio/hal/clock.hpp"
#include "cambio/v4l2/mjpeg_decoder.hpp"
#include "cambio/v4l2/stamp_mapping.hpp"
#include "cambio/v4l2/v4l2_camera_settings.hpp"
#include "cambio/v4l2/video_device.hpp"

namespace cambio::v4l2 {

/// What configure() set on the device and read back from it.
struct ConfiguredStream {
  StreamFormat format;
  FrameInterval interval;
  std::optional<double> exposure_us;  ///< Read back; nullopt when the rig set none.
  std::optional<std::int32_t> gain;
  std::optional<std::int32_t> white_balance_k;
};

/// Counters of one camera's frames, written by the camera loop, read by anyone.
struct CaptureCounters {
  std::atomic<std::uint64_t> delivered{0};
  /// Frames never delivered: superseded by a newer one (newest wins), unpaired, damaged
  /// (V4L2_BUF_FLAG_ERROR, or an MJPEG frame that does not decode) or dropped by the driver for
  /// want of a queued buffer (sequence gaps).
  std::atomic<std::uint64_t> dropped{0};
  /// Delivered more than one frame period after their stamp.
  std::atomic<std::uint64_t> late{0};
};

/// One V4L2 device's stream: negotiation and controls at configure, a ring of mmap buffers, and
/// on the loop side non-blocking dequeues that hold the newest few frames (for pairing) and
/// requeue the rest. Lifecycle: configure() (throws) -> activate() -> poll()/deliver() from one
/// loop thread -> deactivate().
class V4l2Capture {
 public:
  /// The most frames held dequeued for pairing; the rest of the ring stays with the driver.
  static constexpr std::size_t kMaxHeld = 2;

  V4l2Capture(const hal::CameraInfo& info, V4l2CameraSettings settings,
              std::unique_ptr<VideoDevice> device, hal::Clock& clock);

  /// Negotiates the rig's format, size and rate (ModeRefused listing what the device offers),
  /// sets and reads back the controls, maps the buffers. Throws DeviceError, ModeRefused or
  /// std::runtime_error, each naming the camera and its device.
  void configure();
  /// Starts streaming, stamping with `mapping` (one for every camera of the run, so two
  /// cameras' stamps differ by what their drivers measured, never by when each was anchored).
  void activate(const StampMapping& mapping);
  void deactivate() noexcept;

  /// Takes every filled buffer the driver has (never waits), holding the newest kMaxHeld.
  /// kOk, or kFault once the device is gone (sticky). Real-time safe.
  hal::Status poll() noexcept;
  /// Stamps (run clock, ns) of the frames held, oldest first.
  std::span<const std::int64_t> held_stamps_ns() const {
    return {held_stamps_ns_.data(), held_count_};
  }
  /// Converts held frame `held_index` into `out` (its stamp and a new sequence number), then
  /// requeues it and every older frame held. Real-time safe.
  hal::Status deliver(std::size_t held_index, hal::Image& out) noexcept;
  /// poll() and deliver the newest frame: kNoNewData when none arrived since the last grab.
  hal::Status grab_newest(hal::Image& out) noexcept;

  const hal::CameraInfo& info() const { return info_; }
  const V4l2CameraSettings& settings() const { return settings_; }
  const ConfiguredStream& stream() const { return stream_; }
  const CaptureCounters& counters() const { return counters_; }
  std::int64_t frame_period_ns() const { return frame_period_ns_; }
  /// Whether the device was lost (ENODEV) or failed while streaming.
  bool faulted() const { return fault_.load(std::memory_order_acquire) != StreamResult::kOk; }
  /// One line: the camera, its device, the negotiated mode, the controls read back.
  std::string describe() const;
  /// Empty, or why the camera faulted, for the run's report.
  std::string fault_message() const;

 private:
  void set_controls();
  hal::Status fail(StreamResult result) noexcept;
  void drop_oldest() noexcept;

  hal::CameraInfo info_;
  V4l2CameraSettings settings_;
  std::unique_ptr<VideoDevice> device_;
  hal::Clock& clock_;
  StampMapping mapping_;
  ConfiguredStream stream_;
  std::unique_ptr<MjpegDecoder> mjpeg_;  ///< For an MJPEG stream: made at configure.
  std::size_t held_capacity_ = 1;
  std::int64_t frame_period_ns_ = 0;
  bool streaming_ = false;

  std::array<FilledBuffer, kMaxHeld> held_{};
  std::array<std::int64_t, kMaxHeld> held_stamps_ns_{};
  std::size_t held_count_ = 0;
  bool have_sequence_ = false;
  std::uint32_t last_sequence_ = 0;
  std::uint64_t next_image_sequence_ = 1;
  std::atomic<StreamResult> fault_{StreamResult::kOk};
  CaptureCounters counters_;
};

}  // namespace cambio::v4l2
