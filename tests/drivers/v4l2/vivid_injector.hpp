#pragma once

// vivid's looped HDMI instances as a camera pair's source, for the guest tests: an Injector
// streams one YUYV frame over and over to an instance's output, which its capture node returns
// (tests/can_vm/v4l2_vivid_vm_test.sh loads the instances). Errors are std::runtime_error.

#include <fcntl.h>
#include <linux/v4l2-dv-timings.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace cambio::v4l2::vivid {

constexpr int kWidth = 640;
constexpr int kHeight = 480;

// The kernel's own definition, whose initialiser mixes designated and positional fields (C
// style): clang reports that in C++.
#if defined(__clang__)
#pragma clang diagnostic push
#pragma clang diagnostic ignored "-Wc99-designator"
#pragma clang diagnostic ignored "-Wmissing-field-initializers"
#endif
inline v4l2_dv_timings cea_640x480p59_94() {
  return V4L2_DV_BT_CEA_640X480P59_94;
}
#if defined(__clang__)
#pragma clang diagnostic pop
#endif

inline int xioctl(int fd, unsigned long request, void* argument) {
  int result = 0;
  do {
    result = ioctl(fd, request, argument);
  } while (result == -1 && errno == EINTR);
  return result;
}

/// An ioctl that must succeed: a std::runtime_error naming it otherwise.
inline void check_ioctl(int fd, unsigned long request, void* argument, const char* name) {
  if (xioctl(fd, request, argument) != 0) {
    throw std::runtime_error(std::string(name) + ": " + std::strerror(errno));
  }
}

/// A control of `fd` by its name (vivid's own controls have no fixed id across kernels).
inline std::uint32_t control_named(int fd, const std::string& name) {
  v4l2_query_ext_ctrl query{};
  query.id = V4L2_CTRL_FLAG_NEXT_CTRL | V4L2_CTRL_FLAG_NEXT_COMPOUND;
  while (xioctl(fd, VIDIOC_QUERY_EXT_CTRL, &query) == 0) {
    if (name == query.name) return query.id;
    query.id |= V4L2_CTRL_FLAG_NEXT_CTRL | V4L2_CTRL_FLAG_NEXT_COMPOUND;
  }
  return 0;
}

inline void set_control(int fd, const std::string& name, std::int32_t value) {
  const std::uint32_t id = control_named(fd, name);
  if (id == 0) throw std::runtime_error("no control '" + name + "'");
  v4l2_control control{id, value};
  check_ioctl(fd, VIDIOC_S_CTRL, &control, "VIDIOC_S_CTRL");
}

/// An instance's HDMI output streaming one frame over and over (the loop shows the buffer the
/// output is displaying, so the output must keep one queued), on a thread of its own.
class Injector {
 public:
  Injector(const std::string& output_path, const std::string& capture_path,
           std::vector<std::uint8_t> frame)
      : frame_(std::move(frame)) {
    capture_fd_ = ::open(capture_path.c_str(), O_RDWR | O_NONBLOCK);
    output_fd_ = ::open(output_path.c_str(), O_RDWR | O_NONBLOCK);
    if (capture_fd_ < 0 || output_fd_ < 0) throw std::runtime_error("cannot open vivid's nodes");
  }
  ~Injector() {
    stop_ = true;
    if (pump_.joinable()) pump_.join();
    int type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    (void)xioctl(output_fd_, VIDIOC_STREAMOFF, &type);
    for (auto& [address, length] : maps_) munmap(address, length);
    ::close(output_fd_);
    ::close(capture_fd_);
  }

  /// Both ends at 640x480p59.94 YUYV, looping on, on-screen text off; the output streaming.
  void start() {
    v4l2_dv_timings timings = cea_640x480p59_94();
    check_ioctl(capture_fd_, VIDIOC_S_DV_TIMINGS, &timings, "VIDIOC_S_DV_TIMINGS");
    timings = cea_640x480p59_94();
    check_ioctl(output_fd_, VIDIOC_S_DV_TIMINGS, &timings, "VIDIOC_S_DV_TIMINGS");
    set_control(capture_fd_, "Loop Video", 1);
    set_control(capture_fd_, "OSD Text Mode", 2);  // None
    v4l2_format format{};
    format.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    format.fmt.pix = {};
    format.fmt.pix.width = kWidth;
    format.fmt.pix.height = kHeight;
    format.fmt.pix.pixelformat = V4L2_PIX_FMT_YUYV;
    format.fmt.pix.field = V4L2_FIELD_NONE;
    check_ioctl(output_fd_, VIDIOC_S_FMT, &format, "VIDIOC_S_FMT");
    if (format.fmt.pix.bytesperline != 2u * kWidth) throw std::runtime_error("vivid: not packed");
    v4l2_requestbuffers request{};
    request.count = 3;
    request.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    request.memory = V4L2_MEMORY_MMAP;
    check_ioctl(output_fd_, VIDIOC_REQBUFS, &request, "VIDIOC_REQBUFS");
    for (std::uint32_t index = 0; index < request.count; ++index) {
      v4l2_buffer buffer{};
      buffer.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
      buffer.memory = V4L2_MEMORY_MMAP;
      buffer.index = index;
      check_ioctl(output_fd_, VIDIOC_QUERYBUF, &buffer, "VIDIOC_QUERYBUF");
      void* address = mmap(nullptr, buffer.length, PROT_READ | PROT_WRITE, MAP_SHARED, output_fd_,
                           buffer.m.offset);
      if (address == MAP_FAILED) throw std::runtime_error("vivid: mmap failed");
      maps_.emplace_back(address, buffer.length);
      std::memcpy(address, frame_.data(), frame_.size());
      buffer.bytesused = static_cast<std::uint32_t>(frame_.size());
      check_ioctl(output_fd_, VIDIOC_QBUF, &buffer, "VIDIOC_QBUF");
    }
    int type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    check_ioctl(output_fd_, VIDIOC_STREAMON, &type, "VIDIOC_STREAMON");
    pump_ = std::thread([this] { pump(); });
  }
  int capture_fd() const { return capture_fd_; }

 private:
  void pump() {
    while (!stop_) {
      pollfd wait{output_fd_, POLLOUT, 0};
      if (::poll(&wait, 1, 50) <= 0) continue;
      v4l2_buffer buffer{};
      buffer.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
      buffer.memory = V4L2_MEMORY_MMAP;
      if (xioctl(output_fd_, VIDIOC_DQBUF, &buffer) != 0) continue;
      buffer.bytesused = static_cast<std::uint32_t>(frame_.size());
      (void)xioctl(output_fd_, VIDIOC_QBUF, &buffer);
    }
  }

  std::vector<std::uint8_t> frame_;
  int capture_fd_ = -1;
  int output_fd_ = -1;
  std::vector<std::pair<void*, std::size_t>> maps_;
  std::atomic<bool> stop_{false};
  std::thread pump_;
};

}  // namespace cambio::v4l2::vivid
