// The v4l2 backend on a real kernel V4L2 stack: the vivid driver in the QEMU guest
// (tests/can_vm/v4l2_vivid_vm_test.sh loads it with two instances whose HDMI output loops to
// their HDMI input, and a third with a webcam input). Frames are injected through each
// instance's output device and must come back to the backend's cameras byte for byte (raw) and
// as BT.601's closed form after conversion; stamps monotonic and paired within half a period;
// refusals list what the device offers; a disconnected device is a camera fault.
// Not discovered on the host (no V4L2 there): run only through the harness.

#include <fcntl.h>
#include <linux/v4l2-dv-timings.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "cambio/hal/monotonic_clock.hpp"
#include "cambio/v4l2/kernel_video_device.hpp"
#include "cambio/v4l2/mode_negotiation.hpp"
#include "cambio/v4l2/v4l2_backend.hpp"
#include "cambio/v4l2/v4l2_rig_check.hpp"
#include "vivid_injector.hpp"

namespace cambio::v4l2 {
namespace {

using vivid::Injector;
using vivid::kHeight;
using vivid::kWidth;
using vivid::set_control;

std::string env(const char* name) {
  const char* value = std::getenv(name);
  if (value == nullptr) throw std::runtime_error(std::string("set ") + name);
  return value;
}

/// Deterministic YUYV content: every byte from a seeded generator, limited range kept so
/// nothing clips (Y' and chroma in [16, 235]).
std::vector<std::uint8_t> injected_frame(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> level(16, 235);
  std::vector<std::uint8_t> frame(static_cast<std::size_t>(kWidth) * kHeight * 2);
  for (auto& byte : frame) byte = static_cast<std::uint8_t>(level(rng));
  return frame;
}

// BT.601 limited range to full-range R'G'B' (ITU-R BT.601-7), real-valued.
std::array<double, 3> bt601_rgb(int y, int cb, int cr) {
  const double luma = 255.0 / 219.0 * (y - 16);
  const double r = luma + 2.0 * (1.0 - 0.299) * 255.0 / 224.0 * (cr - 128);
  const double b = luma + 2.0 * (1.0 - 0.114) * 255.0 / 224.0 * (cb - 128);
  const double g = (luma - 0.299 * r - 0.114 * b) / 0.587;
  return {std::clamp(r, 0.0, 255.0), std::clamp(g, 0.0, 255.0), std::clamp(b, 0.0, 255.0)};
}

/// The largest difference between `image` and the closed form of `frame`.
double worst_difference(const hal::Image& image, const std::vector<std::uint8_t>& frame) {
  double worst = 0.0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::uint8_t* row = frame.data() + static_cast<std::size_t>(y) * 2 * kWidth;
      if (image.format == hal::PixelFormat::kGrey8) {
        const double truth = std::clamp(255.0 / 219.0 * (row[2 * x] - 16), 0.0, 255.0);
        worst = std::max(worst, std::abs(image.row(y)[x] - truth));
        continue;
      }
      const auto truth = bt601_rgb(row[2 * x], row[4 * (x / 2) + 1], row[4 * (x / 2) + 3]);
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(image.row(y)[3 * x + c] - truth[c]));
      }
    }
  }
  return worst;
}

class VividTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    left_injector =
        new Injector(env("CAMBIO_VIVID_LEFT_OUT"), env("CAMBIO_VIVID_LEFT_CAP"), injected_frame(1));
    right_injector = new Injector(env("CAMBIO_VIVID_RIGHT_OUT"), env("CAMBIO_VIVID_RIGHT_CAP"),
                                  injected_frame(2));
    left_injector->start();
    right_injector->start();
  }
  static void TearDownTestSuite() {
    delete left_injector;
    delete right_injector;
  }
  static Injector* left_injector;
  static Injector* right_injector;
};
Injector* VividTest::left_injector = nullptr;
Injector* VividTest::right_injector = nullptr;

std::string refusal(const std::string& device, StreamRequest request) {
  try {
    (void)negotiate_mode(KernelVideoDevice::open(device)->modes(), request, device);
  } catch (const ModeRefused& error) {
    return error.what();
  }
  return "accepted";
}

TEST_F(VividTest, AModeTheWebcamLacksIsRefusedWithWhatItOffers) {
  const std::string webcam = env("CAMBIO_VIVID_WEBCAM");
  const DeviceModes modes = KernelVideoDevice::open(webcam)->modes();
  std::cout << "vivid webcam offers:\n" << describe_modes(modes) << "\n";
  const std::string size = refusal(webcam, {V4L2_PIX_FMT_YUYV, 800, 600, 30.0});
  std::cout << "800x600: " << size << "\n";
  EXPECT_NE(size.find("YUYV at 800x600 is not offered; the device offers YUYV at 320x180"),
            std::string::npos)
      << size;
  EXPECT_NE(size.find("640x480 ("), std::string::npos) << size;
  const std::string rate = refusal(webcam, {V4L2_PIX_FMT_YUYV, 640, 480, 7.0});
  std::cout << "7 Hz: " << rate << "\n";
  EXPECT_NE(rate.find("YUYV 640x480 at 7 Hz is not offered; the device offers 640x480 ("),
            std::string::npos)
      << rate;
  const std::string format = refusal(webcam, {fourcc('M', 'J', 'P', 'G'), 640, 480, 30.0});
  EXPECT_NE(format.find("pixel format MJPG is not offered; the device offers YUYV"),
            std::string::npos)
      << format;
}

TEST_F(VividTest, TheLoopReturnsTheInjectedBytesRaw) {
  // The kernel's own path, without the backend's conversion: a dequeued buffer equals the
  // injected frame byte for byte.
  auto device = KernelVideoDevice::open(env("CAMBIO_VIVID_LEFT_CAP"));
  const StreamFormat format = device->set_format(V4L2_PIX_FMT_YUYV, kWidth, kHeight);
  ASSERT_EQ(format.width_px, kWidth);
  ASSERT_EQ(format.bytes_per_line, 2u * kWidth);
  ASSERT_GE(device->map_buffers(3), 2u);
  device->start_streaming();
  const auto expected = injected_frame(1);
  FilledBuffer buffer;
  int identical = 0;
  for (int tries = 0; tries < 2000 && identical < 3; ++tries) {
    const StreamResult result = device->dequeue(buffer);
    if (result == StreamResult::kNotReady) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      continue;
    }
    ASSERT_EQ(result, StreamResult::kOk);
    EXPECT_TRUE(buffer.monotonic);
    const auto bytes = device->buffer(buffer.index).first(buffer.bytes_used);
    ASSERT_EQ(bytes.size(), expected.size());
    identical += std::equal(bytes.begin(), bytes.end(), expected.begin()) ? 1 : 0;
    ASSERT_EQ(device->requeue(buffer.index), StreamResult::kOk);
  }
  EXPECT_EQ(identical, 3);
}

hal::CameraInfo camera(const std::string& name, hal::PixelFormat format) {
  hal::CameraInfo info;
  info.name = name;
  info.backend = std::string(V4l2Backend::kName);
  info.intrinsics = {kWidth, kHeight, 500.0, 500.0, 319.5, 239.5};
  info.format = format;
  info.rate_hz = 60.0;
  return info;
}

V4l2CameraSettings settings(const std::string& name, const std::string& device) {
  V4l2CameraSettings s;
  s.camera = name;
  s.device = device;
  s.pixel_format = "YUYV";
  s.frame_rate_hz = 60.0;
  s.buffer_count = 4;
  return s;
}

TEST_F(VividTest, BothEyesDeliverTheInjectedFramesPairedAndAnUnplugIsAFault) {
  hal::HardwareInfo hardware;
  hardware.cameras = {camera("left_eye", hal::PixelFormat::kRgb8),
                      camera("right_eye", hal::PixelFormat::kGrey8)};
  hardware.stereo = hal::StereoPairInfo{"left_eye", "right_eye", 0.1};
  V4l2RigInfo rig;
  rig.cameras = {settings("left_eye", env("CAMBIO_VIVID_LEFT_CAP")),
                 settings("right_eye", env("CAMBIO_VIVID_RIGHT_CAP"))};
  rig.cameras[1].controls.gain = 64;  // vivid has a gain control (and no exposure)
  ASSERT_TRUE(check_v4l2_rig(hardware, rig).empty());
  hal::BackendFactory factory;
  register_v4l2_backend(factory, rig);
  hal::MonotonicClock clock;
  const hal::BackendContext context{&clock, 0, true};
  auto backend = factory.make("v4l2", hardware, context, "the test");
  auto left = backend->make_camera("left_eye");
  auto right = backend->make_camera("right_eye");
  backend->configure();
  const auto* v4l2 = static_cast<const V4l2Backend*>(backend.get());
  EXPECT_EQ(v4l2->capture("right_eye")->stream().gain, 64);
  std::cout << v4l2->capture("left_eye")->describe() << "\n"
            << v4l2->capture("right_eye")->describe() << "\n";
  const std::int64_t start_ns = clock.now_ns();
  backend->activate();

  hal::Image left_image(kWidth, kHeight, hal::PixelFormat::kRgb8);
  hal::Image right_image(kWidth, kHeight, hal::PixelFormat::kGrey8);
  hal::Image first_left = left_image;
  hal::Image first_right = right_image;
  const auto left_frame = injected_frame(1);
  const auto right_frame = injected_frame(2);
  int pairs = 0;
  int identical_pairs = 0;
  std::int64_t last_left_ns = 0;
  std::int64_t last_right_ns = 0;
  const std::int64_t half_period_ns = v4l2->stereo_pair()->max_skew_ns();
  const std::int64_t frame_period_ns = v4l2->capture("left_eye")->frame_period_ns();
  // Poll at the camera loop's pace (100 Hz) for 4 s of the guest's clock.
  while (clock.now_ns() - start_ns < 4'000'000'000 || pairs < 5) {
    ASSERT_LT(clock.now_ns() - start_ns, 60'000'000'000) << "no pairs in 60 s";
    const hal::Status l = left->grab(left_image);
    const hal::Status r = right->grab(right_image);
    ASSERT_EQ(l, r);
    ASSERT_NE(l, hal::Status::kFault);
    if (l == hal::Status::kOk) {
      ++pairs;
      EXPECT_GT(left_image.stamp_ns, last_left_ns);
      EXPECT_GT(right_image.stamp_ns, last_right_ns);
      EXPECT_GE(left_image.stamp_ns, start_ns);
      // vivid stamps a frame at the end of its nominal exposure, reckoned from the stream's start,
      // which its thread may deliver up to a period early; a camera's stamps are in the past.
      EXPECT_LE(left_image.stamp_ns, clock.now_ns() + frame_period_ns);
      EXPECT_LE(std::llabs(left_image.stamp_ns - right_image.stamp_ns), half_period_ns);
      last_left_ns = left_image.stamp_ns;
      last_right_ns = right_image.stamp_ns;
      if (pairs == 1) {
        // The closed form of what was injected, within one level (the 8-bit weights).
        EXPECT_LE(worst_difference(left_image, left_frame), 1.0);
        EXPECT_LE(worst_difference(right_image, right_frame), 0.5);
        first_left = left_image;
        first_right = right_image;
      }
      identical_pairs +=
          left_image.pixels == first_left.pixels && right_image.pixels == first_right.pixels;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(identical_pairs, pairs);
  for (const std::string& line : v4l2->statistics()) std::cout << line << "\n";
  std::cout << "pairs in " << 1e-9 * static_cast<double>(clock.now_ns() - start_ns)
            << " s: " << pairs << "\n";

  // Unplug: vivid's Disconnect button unregisters the instance's nodes as a USB unplug does.
  set_control(right_injector->capture_fd(), "Disconnect", 0);
  hal::Status right_status = hal::Status::kOk;
  for (int k = 0; k < 100 && right_status != hal::Status::kFault; ++k) {
    (void)left->grab(left_image);
    right_status = right->grab(right_image);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(right_status, hal::Status::kFault);
  EXPECT_EQ(v4l2->capture("right_eye")->fault_message(),
            "v4l2: camera 'right_eye' on " + env("CAMBIO_VIVID_RIGHT_CAP") +
                " was unplugged (ENODEV): camera fault");
  EXPECT_FALSE(v4l2->capture("left_eye")->faulted());
  backend->deactivate();
}

}  // namespace
}  // namespace cambio::v4l2
