// A rig's camera_calibration file (config/camera_calibration.hpp): found beside the rig, its
// values replacing the rig's, its mistakes located in its own file; and a camera's distortion key.
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "cambio/config/camera_calibration.hpp"
#include "cambio/config/hardware_description.hpp"
#include "file_test_support.hpp"
#include "rig_test_support.hpp"

namespace cambio::config::test {
namespace {

const std::string kCalibration =
    "cameras:\n"                                                               // 1
    "  eye:\n"                                                                 // 2
    "    width_px: 640\n"                                                      // 3
    "    height_px: 480\n"                                                     // 4
    "    focal_x_px: 601.5\n"                                                  // 5
    "    focal_y_px: 602.25\n"                                                 // 6
    "    principal_point_px: [322.5, 236.0]\n"                                 // 7
    "    distortion: {k1: -0.2, k2: 0.05, p1: 0.001, p2: -0.002, k3: 0.01}\n"  // 8
    "    origin_xyz_m: [0.01, 0.02, 0.03]\n"                                   // 9
    "    origin_rpy_deg: [-90, 0, -90]\n";                                     // 10

/// Loads the small rig naming `calibration` (written beside it as calib.yaml); the issues, or "".
class CalibratedRig : public ::testing::Test {
 protected:
  CalibratedRig() : folder_("cambio_camera_calibration") {}
  std::string rig_path() const { return folder_.path("rig.yaml"); }
  std::string calibration_path() const { return folder_.path("calib.yaml"); }
  void write(const std::string& calibration, const std::string& key_value = "calib.yaml") const {
    std::vector<std::string> lines = kSmallRigLines;
    lines.push_back("camera_calibration: " + key_value);  // Line 35.
    std::ofstream(rig_path()) << join_lines(lines);
    std::ofstream(calibration_path()) << calibration;
  }
  std::string issues() const {
    try {
      (void)load_rig(rig_path());
    } catch (const ConfigError& error) {
      return error.what();
    }
    return "";
  }

  ScratchFolder folder_;
};

TEST_F(CalibratedRig, ReplacesTheCameraValuesFromAFileBesideTheRig) {
  write(kCalibration);
  const RigConfig rig = load_rig(rig_path());
  const CameraConfig& eye = *rig.find_camera("eye");
  EXPECT_DOUBLE_EQ(eye.focal_x_px, 601.5);
  EXPECT_DOUBLE_EQ(eye.focal_y_px, 602.25);
  EXPECT_DOUBLE_EQ(eye.principal_x_px, 322.5);
  EXPECT_DOUBLE_EQ(eye.principal_y_px, 236.0);
  EXPECT_DOUBLE_EQ(eye.distortion.k1, -0.2);
  EXPECT_DOUBLE_EQ(eye.distortion.p2, -0.002);
  EXPECT_DOUBLE_EQ(eye.distortion.k3, 0.01);
  EXPECT_DOUBLE_EQ(eye.mount.xyz_m[2], 0.03);
  EXPECT_NEAR(eye.mount.rpy_rad[0], -std::numbers::pi / 2, 1e-12);
  // The HAL's camera carries the distortion on.
  EXPECT_DOUBLE_EQ(hardware_description(rig).cameras.at(0).distortion.k2, 0.05);
}

TEST_F(CalibratedRig, LocatesItsMistakesInTheCalibrationFile) {
  std::string calibration = kCalibration;
  calibration.replace(calibration.find("  eye:"), 6, "  eyes:");
  write(calibration);
  EXPECT_NE(issues().find(calibration_path() + ":3:5: cameras.eyes: expected a camera of rig "
                                               "\"test\" (eye), found \"eyes\"; did you mean "
                                               "\"eye\"?"),
            std::string::npos)
      << issues();

  calibration = kCalibration;
  calibration.replace(calibration.find("width_px: 640"), 13, "width_px: 1280");
  calibration.replace(calibration.find(", k3: 0.01"), 10, "");
  write(calibration);
  EXPECT_NE(issues().find(calibration_path() +
                          ":3:15: cameras.eye.width_px: expected the rig's 640 for camera \"eye\""),
            std::string::npos)
      << issues();
  EXPECT_NE(issues().find(calibration_path() + ":8:17: cameras.eye.distortion.k3: missing key"),
            std::string::npos)
      << issues();
}

TEST_F(CalibratedRig, NamesAFileItCannotRead) {
  write(kCalibration, "missing.yaml");
  EXPECT_NE(issues().find(rig_path() +
                          ":35:21: camera_calibration: cannot read the camera "
                          "calibration \"" +
                          folder_.path("missing.yaml") + "\": it does not exist"),
            std::string::npos)
      << issues();
}

TEST(CameraDistortionKey, IsReadFromTheRigAndRangeChecked) {
  std::vector<std::string> lines = kSmallRigLines;
  lines.insert(lines.begin() + 32,
               "    distortion: {k1: -0.3, k2: 0.1, p1: 0.0, p2: 0.0, k3: 0.0}");
  EXPECT_DOUBLE_EQ(load_rig_from_string(join_lines(lines), "rig.yaml").cameras[0].distortion.k1,
                   -0.3);
  lines[32] = "    distortion: {k1: -0.3, k2: 0.1, p1: 5.0, p2: 0.0, k3: 0.0}";
  try {
    (void)load_rig_from_string(join_lines(lines), "rig.yaml");
    FAIL() << "p1 = 5 accepted";
  } catch (const ConfigError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("cameras.eye.distortion.p1: expected a number in "
                        "[-1, 1]"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace cambio::config::test
