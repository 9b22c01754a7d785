// The rig file's V4L2 camera keys: the loader's syntax (firmware_config), the backend's settings
// (v4l2_rig_from_config) and the backend's check (check_v4l2_rig), located at the rig's keys as
// check-config and cambio run report them.

#include "cambio/v4l2/v4l2_rig_check.hpp"

#include <gtest/gtest.h>

#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/v4l2/v4l2_rig_from_config.hpp"
#include "rig_test_support.hpp"

namespace cambio::v4l2 {
namespace {

using config::test::small_rig_with;

// The small rig's camera `eye` (lines 27-32) with `keys` after its principal point (line 32).
std::string eye_with(const std::string& keys) {
  return small_rig_with(32, "    principal_point_px: [319.5, 239.5]\n" + keys);
}

/// Every problem of the backend's check, as "line:column: key: message".
std::vector<std::string> check(const std::string& yaml) {
  const config::RigConfig rig = config::load_rig_from_string(yaml, "test.yaml");
  std::vector<std::string> located;
  for (auto& problem :
       check_v4l2_rig(config::hardware_description(rig), v4l2_rig_from_config(rig))) {
    const config::ConfigIssue issue = rig.locate(problem.key_path, problem.message);
    located.push_back(std::to_string(issue.line) + ":" + std::to_string(issue.column) + ": " +
                      issue.key_path + ": " + issue.message);
  }
  return located;
}

TEST(V4l2RigKeys, ACameraEntryReachesTheBackendsSettings) {
  const config::RigConfig rig = config::load_rig_from_string(
      eye_with("    backend: v4l2\n    device: /dev/video0\n    pixel_format: YUYV\n"
               "    frame_rate_hz: 30\n    buffer_count: 6\n"
               "    controls: {exposure_us: 10000, gain: 16, white_balance_k: 4600}"),
      "test.yaml");
  const V4l2RigInfo info = v4l2_rig_from_config(rig);
  const V4l2CameraSettings* eye = info.find("eye");
  ASSERT_NE(eye, nullptr);
  EXPECT_EQ(eye->device, "/dev/video0");
  EXPECT_EQ(eye->pixel_format, "YUYV");
  EXPECT_EQ(eye->frame_rate_hz, 30.0);
  EXPECT_EQ(eye->buffer_count, 6);
  EXPECT_EQ(eye->controls.exposure_us, 10000.0);
  EXPECT_EQ(eye->controls.gain, 16);
  EXPECT_EQ(eye->controls.white_balance_k, 4600);
  EXPECT_TRUE(check_v4l2_rig(config::hardware_description(rig), info).empty());
}

TEST(V4l2RigKeys, AV4l2CameraWithoutItsSettingsIsRefusedAtItsEntry) {
  EXPECT_EQ(check(eye_with("    backend: v4l2")),
            (std::vector<std::string>{
                "28:5: cameras.eye.device: expected the camera's device node (e.g. device: "
                "/dev/video0) for backend v4l2, found none",
                "28:5: cameras.eye.pixel_format: expected the device's pixel format (GREY, YUYV or "
                "MJPG) for backend v4l2, found none",
                "28:5: cameras.eye.frame_rate_hz: expected the rate to stream at (frame_rate_hz) "
                "for backend v4l2, found none"}));
}

TEST(V4l2RigKeys, BadSettingsAreRefusedAtTheirKeys) {
  EXPECT_EQ(check(eye_with("    backend: v4l2\n    device: video0\n    pixel_format: H264\n"
                           "    frame_rate_hz: 30")),
            (std::vector<std::string>{
                "34:13: cameras.eye.device: expected a device node under /dev/ (e.g. /dev/video0 "
                "or /dev/v4l/by-id/...), found 'video0'",
                "35:19: cameras.eye.pixel_format: expected GREY, YUYV or MJPG (the formats this "
                "build reads), found 'H264'"}));
  EXPECT_EQ(check(eye_with("    backend: v4l2\n    device: /dev/../etc/passwd\n"
                           "    pixel_format: GREY\n    frame_rate_hz: 30"))
                .size(),
            1u);
}

TEST(V4l2RigKeys, YuyvNeedsAnEvenWidth) {
  const std::string yaml =
      config::test::patched(config::test::kSmallRigLines, 29, "    width_px: 639");
  std::vector<std::string> lines = config::test::split_lines(yaml);
  lines[31] =
      "    principal_point_px: [319, 239.5]\n    backend: v4l2\n    device: /dev/video0\n"
      "    pixel_format: YUYV\n    frame_rate_hz: 30";
  EXPECT_EQ(check(config::test::join_lines(lines)),
            (std::vector<std::string>{"29:15: cameras.eye.width_px: expected an even width for "
                                      "YUYV (two pixels share their colour), found 639"}));
}

TEST(V4l2RigKeys, ASimCameraGivesNoDevice) {
  EXPECT_EQ(check(eye_with("    device: /dev/video0")),
            (std::vector<std::string>{
                "33:13: cameras.eye.device: expected no V4L2 settings (device, pixel_format, "
                "frame_rate_hz, controls) on a camera whose backend is 'sim'; they are read with "
                "backend: v4l2"}));
}

TEST(V4l2RigKeys, TheLoaderChecksTheKeysOwnSyntax) {
  const auto issues = config::test::issues_of(
      eye_with("    backend: v4l2\n    device: /dev/video0\n    pixel_format: YUYV422\n"
               "    frame_rate_hz: 0\n    controls: {gain: -1, exposure_ms: 10}"));
  std::vector<std::string> messages;
  for (const auto& issue : issues) messages.push_back(issue.key_path + ": " + issue.message);
  ASSERT_EQ(messages.size(), 4u) << config::test::describe(issues);
  EXPECT_EQ(messages[0],
            "cameras.eye.pixel_format: expected a V4L2 pixel format of up to 4 characters "
            "(GREY, YUYV), found 'YUYV422'");
  EXPECT_NE(messages[1].find("cameras.eye.frame_rate_hz: expected a number in (0, 1000]"),
            std::string::npos)
      << messages[1];
  EXPECT_NE(messages[2].find("cameras.eye.controls.gain"), std::string::npos) << messages[2];
  EXPECT_NE(messages[3].find("cameras.eye.controls.exposure_ms"), std::string::npos) << messages[3];
  EXPECT_NE(messages[3].find("exposure_us"), std::string::npos) << messages[3];
}

TEST(V4l2RigKeys, AJointGroupOrTouchSensorOnV4l2IsRefusedAtItsBackend) {
  hal::HardwareInfo hardware;
  hal::JointGroupInfo group;
  group.name = "head";
  group.backend = "v4l2";
  hardware.groups.push_back(group);
  group.name = "arm";
  group.backend = "sim";
  hardware.groups.push_back(group);
  hal::TouchSensorInfo sensor;
  sensor.name = "finger";
  sensor.backend = "v4l2";
  hardware.touch_sensors.push_back(sensor);
  const auto problems = check_v4l2_rig(hardware, V4l2RigInfo{});
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0].key_path, "groups.head.backend");
  EXPECT_EQ(problems[0].message,
            "expected a backend with joints (e.g. sim or socketcan), found 'v4l2', which makes "
            "cameras only");
  EXPECT_EQ(problems[1].key_path, "touch_sensors.finger.backend");
}

TEST(V4l2RigKeys, TwoCamerasOnOneDeviceAndAPairAtTwoRatesAreRefused) {
  hal::HardwareInfo hardware;
  for (const char* name : {"left_eye", "right_eye"}) {
    hal::CameraInfo camera;
    camera.name = name;
    camera.backend = "v4l2";
    camera.intrinsics.width_px = 640;
    hardware.cameras.push_back(camera);
  }
  hardware.stereo = hal::StereoPairInfo{"left_eye", "right_eye", 0.1};
  V4l2RigInfo rig;
  rig.cameras = {{"left_eye", "/dev/video0", "YUYV", 30.0, 4, {}},
                 {"right_eye", "/dev/video0", "YUYV", 15.0, 4, {}}};
  const auto problems = check_v4l2_rig(hardware, rig);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0].key_path, "cameras.right_eye.device");
  EXPECT_EQ(problems[0].message,
            "expected a device of its own, found '/dev/video0', which camera 'left_eye' already "
            "streams from");
  EXPECT_EQ(problems[1].key_path, "cameras.right_eye.frame_rate_hz");
  EXPECT_NE(problems[1].message.find("expected the stereo pair's cameras at one rate"),
            std::string::npos);
}

}  // namespace
}  // namespace cambio::v4l2
