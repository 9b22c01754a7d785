// The v4l2 backend's mode negotiation (drivers/v4l2/src/mode_negotiation.cpp): what a device
// offers (VIDIOC_ENUM_FMT / ENUM_FRAMESIZES / ENUM_FRAMEINTERVALS) against the rig's request.

#include "cambio/v4l2/mode_negotiation.hpp"

#include <gtest/gtest.h>

namespace cambio::v4l2 {
namespace {

// A UVC webcam's list: YUYV at two sizes, 30 and 15 Hz at the small one; GREY at one size.
DeviceModes webcam() {
  return {{kFourccYuyv,
           {FrameSizeOffer::discrete(640, 480, {{1, 30}, {1, 15}}),
            FrameSizeOffer::discrete(1280, 720, {{1001, 30000}})}},
          {kFourccGrey, {FrameSizeOffer::discrete(640, 480, {{1, 60}})}}};
}

std::string refusal(const DeviceModes& modes, const StreamRequest& request) {
  try {
    (void)negotiate_mode(modes, request, "/dev/video0");
  } catch (const ModeRefused& error) {
    return error.what();
  }
  return "accepted";
}

TEST(V4l2ModeNegotiation, FourccTextIsTheCodesCharacters) {
  EXPECT_EQ(fourcc_text(kFourccYuyv), "YUYV");
  EXPECT_EQ(fourcc_text(0x56595559u), "YUYV");  // v4l2_fourcc('Y','U','Y','V') from videodev2.h
  EXPECT_EQ(fourcc_text(kFourccGrey), "GREY");
}

TEST(V4l2ModeNegotiation, AnOfferedModeGivesItsInterval) {
  const FrameInterval interval = negotiate_mode(webcam(), {kFourccYuyv, 640, 480, 15.0}, "d");
  EXPECT_EQ(interval.numerator, 1u);
  EXPECT_EQ(interval.denominator, 15u);
}

TEST(V4l2ModeNegotiation, ThirtyHertzMatches29_97) {
  const FrameInterval interval = negotiate_mode(webcam(), {kFourccYuyv, 1280, 720, 30.0}, "d");
  EXPECT_EQ(interval.numerator, 1001u);
  EXPECT_EQ(interval.denominator, 30000u);
}

TEST(V4l2ModeNegotiation, AFormatNotOfferedListsTheFormats) {
  EXPECT_EQ(refusal(webcam(), {fourcc('M', 'J', 'P', 'G'), 640, 480, 30.0}),
            "/dev/video0: pixel format MJPG is not offered; the device offers YUYV, GREY");
}

TEST(V4l2ModeNegotiation, ASizeNotOfferedListsTheFormatsSizesAndRates) {
  EXPECT_EQ(refusal(webcam(), {kFourccYuyv, 800, 600, 30.0}),
            "/dev/video0: YUYV at 800x600 is not offered; the device offers YUYV at "
            "640x480 (30, 15 Hz), 1280x720 (29.97 Hz)");
}

TEST(V4l2ModeNegotiation, ARateNotOfferedListsTheSizesRates) {
  EXPECT_EQ(refusal(webcam(), {kFourccYuyv, 640, 480, 25.0}),
            "/dev/video0: YUYV 640x480 at 25 Hz is not offered; the device offers 640x480 "
            "(30, 15 Hz)");
}

TEST(V4l2ModeNegotiation, StepwiseSizesAcceptWhatIsOnTheirSteps) {
  const DeviceModes modes = {{kFourccGrey, {{16, 1920, 16, 16, 1080, 8, {}}}}};
  EXPECT_EQ(refusal(modes, {kFourccGrey, 640, 480, 30.0}), "accepted");
  EXPECT_EQ(refusal(modes, {kFourccGrey, 648, 480, 30.0}),
            "/dev/video0: GREY at 648x480 is not offered; the device offers GREY at 16x16 to "
            "1920x1080 in steps of 16x8");
}

TEST(V4l2ModeNegotiation, ASizeWithoutRatesAsksForTheRequestedRate) {
  const DeviceModes modes = {{kFourccYuyv, {FrameSizeOffer::discrete(640, 480)}}};
  const FrameInterval interval = negotiate_mode(modes, {kFourccYuyv, 640, 480, 60.0}, "d");
  EXPECT_NEAR(interval.rate_hz(), 60.0, 1e-3);
}

TEST(V4l2ModeNegotiation, DescribeModesIsOneLinePerFormat) {
  EXPECT_EQ(describe_modes(webcam()),
            "YUYV: 640x480 (30, 15 Hz), 1280x720 (29.97 Hz)\nGREY: 640x480 (60 Hz)");
}

}  // namespace
}  // namespace cambio::v4l2
