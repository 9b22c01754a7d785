// One V4L2 camera's stream and the stereo pair over fake devices (fake_video_device.hpp): newest
// frame wins, drops and late frames counted, stamps on the run's clock, controls read back,
// unplug as a fault, pairing by stamps, and no allocation in the loop side.

#include "cambio/v4l2/v4l2_capture.hpp"

#include <linux/videodev2.h>

#include <gtest/gtest.h>

#include "cambio/hal/manual_clock.hpp"
#include "cambio/runtime/allocation_counter.hpp"
#include "cambio/v4l2/mode_negotiation.hpp"
#include "cambio/v4l2/v4l2_stereo_pair.hpp"
#include "fake_video_device.hpp"

namespace cambio::v4l2 {
namespace {

using test::FakeVideoDevice;

constexpr int kWidth = 8;
constexpr int kHeight = 4;
constexpr std::int64_t kPeriodNs = 33'333'333;

hal::CameraInfo grey_camera(std::string name = "left_eye") {
  hal::CameraInfo info;
  info.name = std::move(name);
  info.backend = "v4l2";
  info.intrinsics = {kWidth, kHeight, 10.0, 10.0, 3.5, 1.5};
  info.format = hal::PixelFormat::kGrey8;
  info.rate_hz = 30.0;
  return info;
}

V4l2CameraSettings grey_settings(std::string name = "left_eye") {
  V4l2CameraSettings settings;
  settings.camera = std::move(name);
  settings.device = "/dev/video0";
  settings.pixel_format = "GREY";
  settings.frame_rate_hz = 30.0;
  settings.buffer_count = 4;
  return settings;
}

DeviceModes grey_modes() {
  return {{kFourccGrey, {FrameSizeOffer::discrete(kWidth, kHeight, {{1, 30}, {1, 60}})}}};
}

std::vector<std::uint8_t> frame_of(std::uint8_t level) {
  return std::vector<std::uint8_t>(kWidth * kHeight, level);
}

struct Rig {
  hal::ManualClock clock{5'000'000'000};
  FakeVideoDevice* device = nullptr;
  std::unique_ptr<V4l2Capture> capture;

  explicit Rig(V4l2CameraSettings settings = grey_settings(),
               hal::CameraInfo info = grey_camera()) {
    auto owned = std::make_unique<FakeVideoDevice>(grey_modes(), settings.device);
    device = owned.get();
    capture = std::make_unique<V4l2Capture>(info, settings, std::move(owned), clock);
  }
  void start() {
    capture->configure();
    StampMapping mapping;
    mapping.anchor(clock.now_ns(), monotonic_now_ns());
    capture->activate(mapping);
  }
};

TEST(V4l2Capture, ConfigureAsksForTheNegotiatedModeAndBuffers) {
  Rig rig;
  rig.start();
  EXPECT_EQ(rig.device->format().fourcc, kFourccGrey);
  EXPECT_EQ(rig.device->interval().denominator, 30u);
  EXPECT_EQ(rig.capture->frame_period_ns(), kPeriodNs);
  EXPECT_EQ(rig.device->queued(), 4u);
  EXPECT_EQ(rig.capture->describe(), "v4l2: camera 'left_eye' on /dev/video0: GREY 8x4 at 30 Hz");
}

TEST(V4l2Capture, AModeTheDeviceLacksIsRefusedNamingCameraAndOffers) {
  V4l2CameraSettings settings = grey_settings();
  settings.frame_rate_hz = 25.0;
  Rig rig(settings);
  try {
    rig.capture->configure();
    FAIL() << "25 Hz was accepted";
  } catch (const ModeRefused& error) {
    EXPECT_STREQ(error.what(),
                 "v4l2: camera 'left_eye': /dev/video0: GREY 8x4 at 25 Hz is not offered; the "
                 "device offers 8x4 (30, 60 Hz)");
  }
}

TEST(V4l2Capture, NoFrameIsNoNewDataNeverAWait) {
  Rig rig;
  rig.start();
  hal::Image out(kWidth, kHeight, hal::PixelFormat::kGrey8);
  EXPECT_EQ(rig.capture->grab_newest(out), hal::Status::kNoNewData);
  EXPECT_EQ(out.sequence, 0u);
}

TEST(V4l2Capture, TheNewestFrameWinsAndTheOthersCountAsDropped) {
  Rig rig;
  rig.start();
  const std::int64_t t0 = 1'000'000'000;
  ASSERT_TRUE(rig.device->fill(t0, frame_of(10)));
  ASSERT_TRUE(rig.device->fill(t0 + kPeriodNs, frame_of(20)));
  ASSERT_TRUE(rig.device->fill(t0 + 2 * kPeriodNs, frame_of(30)));
  hal::Image out(kWidth, kHeight, hal::PixelFormat::kGrey8);
  ASSERT_EQ(rig.capture->grab_newest(out), hal::Status::kOk);
  EXPECT_EQ(out.pixels, frame_of(30));
  EXPECT_EQ(out.sequence, 1u);
  EXPECT_EQ(rig.capture->counters().delivered.load(), 1u);
  EXPECT_EQ(rig.capture->counters().dropped.load(), 2u);
  // Every buffer went back to the driver: the ring keeps streaming.
  EXPECT_EQ(rig.device->queued(), 4u);
  EXPECT_EQ(rig.capture->grab_newest(out), hal::Status::kNoNewData);
}

TEST(V4l2Capture, FramesTheDriverLostForWantOfABufferAreCounted) {
  Rig rig;
  rig.start();
  // Four buffers: frames 5 and 6 find none queued and are lost (sequence gaps 4 -> 7).
  for (int k = 0; k < 4; ++k) ASSERT_TRUE(rig.device->fill(k * kPeriodNs, frame_of(1)));
  EXPECT_FALSE(rig.device->fill(4 * kPeriodNs, frame_of(2)));
  EXPECT_FALSE(rig.device->fill(5 * kPeriodNs, frame_of(3)));
  hal::Image out(kWidth, kHeight, hal::PixelFormat::kGrey8);
  ASSERT_EQ(rig.capture->grab_newest(out), hal::Status::kOk);
  ASSERT_TRUE(rig.device->fill(6 * kPeriodNs, frame_of(4)));
  ASSERT_EQ(rig.capture->grab_newest(out), hal::Status::kOk);
  EXPECT_EQ(out.pixels, frame_of(4));
  // 3 superseded in the first grab, 2 lost by the driver.
  EXPECT_EQ(rig.capture->counters().dropped.load(), 5u);
  EXPECT_EQ(rig.capture->counters().delivered.load(), 2u);
}

TEST(V4l2Capture, StampsAreTheDriversMovedOntoTheRunsClock) {
  Rig rig;
  const std::int64_t before_ns = monotonic_now_ns();
  rig.start();
  const std::int64_t after_ns = monotonic_now_ns();
  // The run's clock reads 5 s at activation; the device's monotonic stamp 2 ms after the
  // activation's monotonic instant lands 2 ms after 5 s, to the anchor's read-out gap.
  ASSERT_TRUE(rig.device->fill(after_ns + 2'000'000, frame_of(9)));
  hal::Image out(kWidth, kHeight, hal::PixelFormat::kGrey8);
  ASSERT_EQ(rig.capture->grab_newest(out), hal::Status::kOk);
  EXPECT_GE(out.stamp_ns, 5'000'000'000 + 2'000'000);
  EXPECT_LE(out.stamp_ns, 5'000'000'000 + 2'000'000 + (after_ns - before_ns));
}

TEST(V4l2Capture, ADriverWithoutMonotonicStampsIsStampedOnArrival) {
  Rig rig;
  rig.start();
  rig.clock.advance_to_ns(7'000'000'000);
  ASSERT_TRUE(rig.device->fill(123, frame_of(9), /*monotonic=*/false));
  hal::Image out(kWidth, kHeight, hal::PixelFormat::kGrey8);
  ASSERT_EQ(rig.capture->grab_newest(out), hal::Status::kOk);
  EXPECT_EQ(out.stamp_ns, 7'000'000'000);
}

TEST(V4l2Capture, AFrameOlderThanAPeriodWhenDeliveredIsLate) {
  Rig rig;
  rig.start();
  ASSERT_TRUE(rig.device->fill(monotonic_now_ns(), frame_of(1)));
  rig.clock.advance_to_ns(rig.clock.now_ns() + 2 * kPeriodNs);
  hal::Image out(kWidth, kHeight, hal::PixelFormat::kGrey8);
  ASSERT_EQ(rig.capture->grab_newest(out), hal::Status::kOk);
  EXPECT_EQ(rig.capture->counters().late.load(), 1u);
  // Stamped as the run's clock reads now: fresh.
  ASSERT_TRUE(rig.device->fill(monotonic_now_ns() + 2 * kPeriodNs, frame_of(2)));
  ASSERT_EQ(rig.capture->grab_newest(out), hal::Status::kOk);
  EXPECT_EQ(rig.capture->counters().late.load(), 1u);
}

TEST(V4l2Capture, AnUnpluggedDeviceIsAStickyFaultWithAMessage) {
  Rig rig;
  rig.start();
  hal::Image out(kWidth, kHeight, hal::PixelFormat::kGrey8);
  EXPECT_TRUE(rig.capture->fault_message().empty());
  rig.device->gone = true;
  EXPECT_EQ(rig.capture->grab_newest(out), hal::Status::kFault);
  rig.device->gone = false;
  EXPECT_EQ(rig.capture->grab_newest(out), hal::Status::kFault);
  EXPECT_EQ(rig.capture->fault_message(),
            "v4l2: camera 'left_eye' on /dev/video0 was unplugged (ENODEV): camera fault");
}

TEST(V4l2Capture, ControlsAreSetWithTheirAutoModesOffAndReadBack) {
  V4l2CameraSettings settings = grey_settings();
  settings.controls.exposure_us = 10'040.0;  // 100.4 units of 100 us: 100
  settings.controls.gain = 300;
  settings.controls.white_balance_k = 4600;
  Rig rig(settings);
  rig.device->controls[V4L2_CID_EXPOSURE_AUTO] = {{0, 3, 1}, V4L2_EXPOSURE_APERTURE_PRIORITY};
  rig.device->controls[V4L2_CID_EXPOSURE_ABSOLUTE] = {{1, 5000, 1}, 300};
  rig.device->controls[V4L2_CID_GAIN] = {{0, 1000, 1}, 0};
  rig.device->controls[V4L2_CID_AUTO_WHITE_BALANCE] = {{0, 1, 1}, 1};
  rig.device->controls[V4L2_CID_WHITE_BALANCE_TEMPERATURE] = {{2800, 6500, 10}, 5000};
  rig.start();
  EXPECT_EQ(rig.device->controls[V4L2_CID_EXPOSURE_AUTO].value, V4L2_EXPOSURE_MANUAL);
  EXPECT_EQ(rig.device->controls[V4L2_CID_AUTO_WHITE_BALANCE].value, 0);
  EXPECT_EQ(rig.capture->stream().exposure_us, 10'000.0);
  EXPECT_EQ(rig.capture->stream().gain, 300);
  EXPECT_EQ(rig.capture->stream().white_balance_k, 4600);
  EXPECT_EQ(rig.capture->describe(),
            "v4l2: camera 'left_eye' on /dev/video0: GREY 8x4 at 30 Hz, exposure 10000 us, gain "
            "300, white balance 4600 K");
}

TEST(V4l2Capture, AControlTheDeviceLacksOrCannotTakeIsRefused) {
  V4l2CameraSettings settings = grey_settings();
  settings.controls.gain = 300;
  Rig missing(settings);
  EXPECT_THROW(
      {
        try {
          missing.capture->configure();
        } catch (const std::runtime_error& error) {
          EXPECT_STREQ(error.what(),
                       "v4l2: camera 'left_eye' on /dev/video0: the device has no "
                       "gain control");
          throw;
        }
      },
      std::runtime_error);
  Rig out_of_range(settings);
  out_of_range.device->controls[V4L2_CID_GAIN] = {{0, 255, 1}, 0};
  try {
    out_of_range.capture->configure();
    FAIL() << "gain 300 was accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(),
                 "v4l2: camera 'left_eye' on /dev/video0: gain 300 is outside the "
                 "device's range [0, 255]");
  }
}

TEST(V4l2Capture, TheLoopSideNeverAllocates) {
  V4l2CameraSettings settings = grey_settings();
  hal::CameraInfo info = grey_camera();
  info.format = hal::PixelFormat::kRgb8;
  Rig rig(settings, info);
  rig.start();
  hal::Image out(kWidth, kHeight, hal::PixelFormat::kRgb8);
  const auto frame = frame_of(7);
  std::uint64_t allocations = 0;
  for (int k = 0; k < 50; ++k) {
    for (int f = 0; f < k % 3; ++f) (void)rig.device->fill(k * kPeriodNs + f, frame);
    const auto before = runtime::thread_allocation_count();
    (void)rig.capture->grab_newest(out);
    allocations += runtime::thread_allocation_count() - before;
  }
  EXPECT_GT(rig.capture->counters().delivered.load(), 30u);
  EXPECT_EQ(allocations, 0u);
}

// Two free-running eyes at 30 Hz, the right one 25 ms behind: pairing by stamps gives pairs
// 8.3 ms apart (the right frame before the left), never 25 ms, which the SSM would refuse.
TEST(V4l2StereoPair, PairsFreeRunningEyesWithinHalfAPeriod) {
  hal::ManualClock clock(0);
  auto left_device = std::make_unique<FakeVideoDevice>(grey_modes(), "/dev/video0");
  auto right_device = std::make_unique<FakeVideoDevice>(grey_modes(), "/dev/video2");
  FakeVideoDevice& left_fake = *left_device;
  FakeVideoDevice& right_fake = *right_device;
  V4l2Capture left(grey_camera("left_eye"), grey_settings("left_eye"), std::move(left_device),
                   clock);
  V4l2CameraSettings right_settings = grey_settings("right_eye");
  right_settings.device = "/dev/video2";
  V4l2Capture right(grey_camera("right_eye"), right_settings, std::move(right_device), clock);
  StampMapping mapping;
  mapping.anchor(clock.now_ns(), monotonic_now_ns());
  for (V4l2Capture* capture : {&left, &right}) {
    capture->configure();
    capture->activate(mapping);
  }
  V4l2StereoPair pair(left, right);
  EXPECT_EQ(pair.max_skew_ns(), kPeriodNs / 2);
  hal::Image left_image(kWidth, kHeight, hal::PixelFormat::kGrey8);
  hal::Image right_image(kWidth, kHeight, hal::PixelFormat::kGrey8);
  const std::int64_t t0 = monotonic_now_ns();
  int pairs = 0;
  std::uint64_t allocations = 0;
  for (int k = 0; k < 30; ++k) {
    const std::int64_t t = t0 + k * kPeriodNs;
    (void)left_fake.fill(t, frame_of(static_cast<std::uint8_t>(k)));
    (void)right_fake.fill(t + 25'000'000, frame_of(static_cast<std::uint8_t>(100 + k)));
    const auto before = runtime::thread_allocation_count();
    const hal::Status l = pair.grab(hal::Eye::kLeft, left_image);
    const hal::Status r = pair.grab(hal::Eye::kRight, right_image);
    allocations += runtime::thread_allocation_count() - before;
    ASSERT_EQ(l, r) << "cycle " << k;
    if (l != hal::Status::kOk) continue;
    ++pairs;
    EXPECT_LE(std::llabs(left_image.stamp_ns - right_image.stamp_ns), kPeriodNs / 2);
    // Left frame k pairs with right frame k - 1 (25 ms after left k - 1, 8.3 ms before left k).
    EXPECT_EQ(left_image.pixels[0], k);
    EXPECT_EQ(right_image.pixels[0], 100 + k - 1);
  }
  EXPECT_EQ(pairs, 29);  // Cycle 0 has no right frame before left frame 0.
  EXPECT_EQ(pair.counters().pairs.load(), 29u);
  EXPECT_EQ(pair.counters().max_skew_ns.load(), kPeriodNs - 25'000'000);
  EXPECT_EQ(allocations, 0u);
}

TEST(V4l2StereoPair, AnUnpluggedEyeFaultsItsOwnGrab) {
  hal::ManualClock clock(0);
  auto left_device = std::make_unique<FakeVideoDevice>(grey_modes(), "/dev/video0");
  auto right_device = std::make_unique<FakeVideoDevice>(grey_modes(), "/dev/video2");
  FakeVideoDevice& right_fake = *right_device;
  V4l2Capture left(grey_camera("left_eye"), grey_settings("left_eye"), std::move(left_device),
                   clock);
  V4l2Capture right(grey_camera("right_eye"), grey_settings("right_eye"), std::move(right_device),
                    clock);
  StampMapping mapping;
  mapping.anchor(clock.now_ns(), monotonic_now_ns());
  for (V4l2Capture* capture : {&left, &right}) {
    capture->configure();
    capture->activate(mapping);
  }
  V4l2StereoPair pair(left, right);
  right_fake.gone = true;
  hal::Image image(kWidth, kHeight, hal::PixelFormat::kGrey8);
  EXPECT_EQ(pair.grab(hal::Eye::kLeft, image), hal::Status::kNoNewData);
  EXPECT_EQ(pair.grab(hal::Eye::kRight, image), hal::Status::kFault);
  EXPECT_TRUE(right.faulted());
  EXPECT_FALSE(left.faulted());
}

}  // namespace
}  // namespace cambio::v4l2
