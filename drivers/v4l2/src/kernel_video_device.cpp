#include "cambio/v4l2/kernel_video_device.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace cambio::v4l2 {

namespace {

int xioctl(int fd, unsigned long request, void* argument) noexcept {
  int result = 0;
  do {
    result = ioctl(fd, request, argument);
  } while (result == -1 && errno == EINTR);
  return result;
}

StreamResult stream_error() noexcept {
  if (errno == EAGAIN) return StreamResult::kNotReady;
  // ENODEV: unplugged; vivid's rmmod and a USB unplug both say so.
  return errno == ENODEV ? StreamResult::kGone : StreamResult::kFailed;
}

std::vector<FrameInterval> intervals_of(int fd, std::uint32_t fourcc, int width, int height) {
  std::vector<FrameInterval> intervals;
  v4l2_frmivalenum ival{};
  ival.pixel_format = fourcc;
  ival.width = static_cast<std::uint32_t>(width);
  ival.height = static_cast<std::uint32_t>(height);
  for (ival.index = 0; xioctl(fd, VIDIOC_ENUM_FRAMEINTERVALS, &ival) == 0; ++ival.index) {
    // Stepwise and continuous ranges are listed by their ends: the rig asks for one rate.
    if (ival.type == V4L2_FRMIVAL_TYPE_DISCRETE) {
      intervals.push_back({ival.discrete.numerator, ival.discrete.denominator});
    } else {
      intervals.push_back({ival.stepwise.min.numerator, ival.stepwise.min.denominator});
      intervals.push_back({ival.stepwise.max.numerator, ival.stepwise.max.denominator});
      break;
    }
  }
  return intervals;
}

}  // namespace

std::unique_ptr<KernelVideoDevice> KernelVideoDevice::open(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    throw DeviceError(path + ": cannot open (" + std::strerror(errno) + ")");
  }
  std::unique_ptr<KernelVideoDevice> device(new KernelVideoDevice(path, fd));
  v4l2_capability capability{};
  if (xioctl(fd, VIDIOC_QUERYCAP, &capability) != 0) device->fail("VIDIOC_QUERYCAP");
  const std::uint32_t caps = (capability.capabilities & V4L2_CAP_DEVICE_CAPS) != 0
                                 ? capability.device_caps
                                 : capability.capabilities;
  if ((caps & V4L2_CAP_VIDEO_CAPTURE) == 0 || (caps & V4L2_CAP_STREAMING) == 0) {
    throw DeviceError(path + ": '" + reinterpret_cast<const char*>(capability.card) +
                      "' is not a single-planar video capture device with streaming I/O");
  }
  return device;
}

KernelVideoDevice::~KernelVideoDevice() {
  stop_streaming();
  unmap_buffers();
  ::close(fd_);
}

void KernelVideoDevice::fail(const char* call) const {
  throw DeviceError(path_ + ": " + call + " failed (" + std::strerror(errno) + ")");
}

DeviceModes KernelVideoDevice::modes() {
  DeviceModes modes;
  v4l2_fmtdesc description{};
  description.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  for (description.index = 0; xioctl(fd_, VIDIOC_ENUM_FMT, &description) == 0;
       ++description.index) {
    FormatOffer format;
    format.fourcc = description.pixelformat;
    v4l2_frmsizeenum size{};
    size.pixel_format = format.fourcc;
    for (size.index = 0; xioctl(fd_, VIDIOC_ENUM_FRAMESIZES, &size) == 0; ++size.index) {
      if (size.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
        const int w = static_cast<int>(size.discrete.width);
        const int h = static_cast<int>(size.discrete.height);
        format.sizes.push_back(
            FrameSizeOffer::discrete(w, h, intervals_of(fd_, format.fourcc, w, h)));
        continue;
      }
      const auto& s = size.stepwise;
      format.sizes.push_back({static_cast<int>(s.min_width),
                              static_cast<int>(s.max_width),
                              static_cast<int>(s.step_width),
                              static_cast<int>(s.min_height),
                              static_cast<int>(s.max_height),
                              static_cast<int>(s.step_height),
                              {}});
      break;
    }
    if (format.sizes.empty()) {
      // The driver enumerates no sizes (an HDMI input: its size is its signal's): the current
      // one is what it offers.
      v4l2_format current{};
      current.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      if (xioctl(fd_, VIDIOC_G_FMT, &current) != 0) fail("VIDIOC_G_FMT");
      format.sizes.push_back(FrameSizeOffer::discrete(static_cast<int>(current.fmt.pix.width),
                                                      static_cast<int>(current.fmt.pix.height)));
    }
    modes.push_back(std::move(format));
  }
  if (errno != EINVAL) fail("VIDIOC_ENUM_FMT");
  return modes;
}

StreamFormat KernelVideoDevice::set_format(std::uint32_t fourcc, int width_px, int height_px) {
  v4l2_format format{};
  format.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  format.fmt.pix.pixelformat = fourcc;
  format.fmt.pix.width = static_cast<std::uint32_t>(width_px);
  format.fmt.pix.height = static_cast<std::uint32_t>(height_px);
  format.fmt.pix.field = V4L2_FIELD_NONE;
  if (xioctl(fd_, VIDIOC_S_FMT, &format) != 0) fail("VIDIOC_S_FMT");
  return {format.fmt.pix.pixelformat, static_cast<int>(format.fmt.pix.width),
          static_cast<int>(format.fmt.pix.height), format.fmt.pix.bytesperline,
          format.fmt.pix.sizeimage};
}

FrameInterval KernelVideoDevice::set_frame_interval(FrameInterval interval) {
  v4l2_streamparm parameters{};
  parameters.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(fd_, VIDIOC_G_PARM, &parameters) != 0) return {};
  if ((parameters.parm.capture.capability & V4L2_CAP_TIMEPERFRAME) != 0) {
    parameters.parm.capture.timeperframe = {interval.numerator, interval.denominator};
    if (xioctl(fd_, VIDIOC_S_PARM, &parameters) != 0) fail("VIDIOC_S_PARM");
  }
  const auto& set = parameters.parm.capture.timeperframe;
  return {set.numerator, set.denominator};
}

std::optional<ControlRange> KernelVideoDevice::query_control(std::uint32_t id) {
  v4l2_queryctrl query{};
  query.id = id;
  if (xioctl(fd_, VIDIOC_QUERYCTRL, &query) != 0) {
    if (errno == EINVAL) return std::nullopt;
    fail("VIDIOC_QUERYCTRL");
  }
  if ((query.flags & V4L2_CTRL_FLAG_DISABLED) != 0) return std::nullopt;
  return ControlRange{query.minimum, query.maximum, query.step};
}

void KernelVideoDevice::set_control(std::uint32_t id, std::int32_t value) {
  v4l2_control control{id, value};
  if (xioctl(fd_, VIDIOC_S_CTRL, &control) != 0) fail("VIDIOC_S_CTRL");
}

std::int32_t KernelVideoDevice::control(std::uint32_t id) {
  v4l2_control control{id, 0};
  if (xioctl(fd_, VIDIOC_G_CTRL, &control) != 0) fail("VIDIOC_G_CTRL");
  return control.value;
}

std::size_t KernelVideoDevice::map_buffers(std::size_t count) {
  unmap_buffers();
  v4l2_requestbuffers request{};
  request.count = static_cast<std::uint32_t>(count);
  request.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  request.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_REQBUFS, &request) != 0) fail("VIDIOC_REQBUFS");
  if (request.count < 2) {
    throw DeviceError(path_ + ": the driver granted " + std::to_string(request.count) +
                      " buffer(s); streaming needs at least 2");
  }
  for (std::uint32_t index = 0; index < request.count; ++index) {
    v4l2_buffer buffer{};
    buffer.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buffer.memory = V4L2_MEMORY_MMAP;
    buffer.index = index;
    if (xioctl(fd_, VIDIOC_QUERYBUF, &buffer) != 0) fail("VIDIOC_QUERYBUF");
    void* address =
        mmap(nullptr, buffer.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, buffer.m.offset);
    if (address == MAP_FAILED) fail("mmap");
    mappings_.push_back({address, buffer.length});
  }
  return mappings_.size();
}

void KernelVideoDevice::unmap_buffers() noexcept {
  for (const Mapping& mapping : mappings_) munmap(mapping.address, mapping.length);
  mappings_.clear();
}

void KernelVideoDevice::start_streaming() {
  for (std::uint32_t index = 0; index < mappings_.size(); ++index) {
    if (requeue(index) != StreamResult::kOk) fail("VIDIOC_QBUF");
  }
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(fd_, VIDIOC_STREAMON, &type) != 0) fail("VIDIOC_STREAMON");
  streaming_ = true;
}

void KernelVideoDevice::stop_streaming() noexcept {
  if (!streaming_) return;
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  (void)xioctl(fd_, VIDIOC_STREAMOFF, &type);  // Fails only on a device already gone.
  streaming_ = false;
}

StreamResult KernelVideoDevice::dequeue(FilledBuffer& out) noexcept {
  v4l2_buffer buffer{};
  buffer.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buffer.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_DQBUF, &buffer) != 0) return stream_error();
  out.index = buffer.index;
  out.bytes_used = buffer.bytesused;
  out.sequence = buffer.sequence;
  out.stamp_ns = static_cast<std::int64_t>(buffer.timestamp.tv_sec) * 1'000'000'000 +
                 static_cast<std::int64_t>(buffer.timestamp.tv_usec) * 1'000;
  out.monotonic =
      (buffer.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
  out.corrupted = (buffer.flags & V4L2_BUF_FLAG_ERROR) != 0;
  return StreamResult::kOk;
}

StreamResult KernelVideoDevice::requeue(std::uint32_t index) noexcept {
  v4l2_buffer buffer{};
  buffer.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buffer.memory = V4L2_MEMORY_MMAP;
  buffer.index = index;
  return xioctl(fd_, VIDIOC_QBUF, &buffer) == 0 ? StreamResult::kOk : stream_error();
}

std::span<const std::uint8_t> KernelVideoDevice::buffer(std::uint32_t index) const noexcept {
  if (index >= mappings_.size()) return {};
  return {static_cast<const std::uint8_t*>(mappings_[index].address), mappings_[index].length};
}

}  // namespace cambio::v4l2
