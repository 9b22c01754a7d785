#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cambio/v4l2/video_device.hpp"

namespace cambio::v4l2 {

/// A capture device node (/dev/videoN) driven with the raw V4L2 ioctls of linux/videodev2.h,
/// opened non-blocking so that VIDIOC_DQBUF answers EAGAIN instead of waiting, with memory-mapped
/// streaming (V4L2_MEMORY_MMAP). Every ioctl is retried on EINTR and checked.
class KernelVideoDevice final : public VideoDevice {
 public:
  /// Opens `path` and checks it can capture video by streaming (VIDIOC_QUERYCAP). Throws
  /// DeviceError naming the path otherwise.
  static std::unique_ptr<KernelVideoDevice> open(const std::string& path);
  ~KernelVideoDevice() override;
  KernelVideoDevice(const KernelVideoDevice&) = delete;
  KernelVideoDevice& operator=(const KernelVideoDevice&) = delete;

  const std::string& path() const override { return path_; }
  DeviceModes modes() override;
  StreamFormat set_format(std::uint32_t fourcc, int width_px, int height_px) override;
  FrameInterval set_frame_interval(FrameInterval interval) override;
  std::optional<ControlRange> query_control(std::uint32_t id) override;
  void set_control(std::uint32_t id, std::int32_t value) override;
  std::int32_t control(std::uint32_t id) override;
  std::size_t map_buffers(std::size_t count) override;
  void start_streaming() override;
  void stop_streaming() noexcept override;
  StreamResult dequeue(FilledBuffer& out) noexcept override;
  StreamResult requeue(std::uint32_t index) noexcept override;
  std::span<const std::uint8_t> buffer(std::uint32_t index) const noexcept override;

 private:
  struct Mapping {
    void* address = nullptr;
    std::size_t length = 0;
  };
  KernelVideoDevice(std::string path, int fd) : path_(std::move(path)), fd_(fd) {}
  [[noreturn]] void fail(const char* call) const;
  void unmap_buffers() noexcept;

  std::string path_;
  int fd_ = -1;
  bool streaming_ = false;
  std::vector<Mapping> mappings_;
};

}  // namespace cambio::v4l2
