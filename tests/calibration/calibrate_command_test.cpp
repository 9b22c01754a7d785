// `cambio calibrate stereo` refusing what it cannot use: each bad argument exits 2 naming it,
// bad image folders exit 2 naming the files, too few usable views exit 1 naming those refused.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "../apps/run_cambio.hpp"
#include "rendered_stereo_views.hpp"

namespace cambio::testing {
namespace {

class CalibrateCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = std::filesystem::temp_directory_path() /
                 ("cambio_calibrate_cli_" + std::to_string(::getpid()) + "_" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(directory_ / "views");
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }
  CommandResult calibrate(const std::string& arguments) const {
    return run_cambio("calibrate " + arguments);
  }
  std::string views() const { return (directory_ / "views").string(); }
  std::string out() const { return (directory_ / "out").string(); }
  void write_grey(const std::string& name, int width_px, int height_px) const {
    cv::imwrite((directory_ / "views" / name).string(),
                cv::Mat(height_px, width_px, CV_8UC1, cv::Scalar(128)));
  }

  std::filesystem::path directory_;
};

void expect_refused(const CommandResult& result, int exit_code, const std::string& text) {
  EXPECT_EQ(result.exit_code, exit_code) << result.output;
  EXPECT_NE(result.output.find(text), std::string::npos) << "expected '" << text << "' in:\n"
                                                         << result.output;
}

TEST_F(CalibrateCommand, RefusesAMissingOrUnknownSubcommand) {
  expect_refused(
      calibrate(""), 2,
      "calibrate: expected a subcommand (the subcommands are: stereo, hand-eye, capture)");
  expect_refused(calibrate("mono"), 2, "unknown subcommand 'mono'");
}

TEST_F(CalibrateCommand, NamesEachMissingArgument) {
  const std::string all =
      "--images " + views() + " --board 9x6 --square-mm 25 --rig cambio --out " + out();
  for (const std::string option : {"images", "board", "square-mm", "rig", "out"}) {
    // Drop "--option value" from the full line.
    std::string line = all;
    const std::size_t at = line.find("--" + option + " ");
    const std::size_t end = line.find(' ', at + option.size() + 3);
    line.erase(at, end == std::string::npos ? std::string::npos : end - at + 1);
    expect_refused(calibrate("stereo " + line), 2, "--" + option + " is required");
  }
}

TEST_F(CalibrateCommand, RefusesABadBoardOrSquareSize) {
  const std::string rest = " --rig cambio --images " + views() + " --out " + out();
  for (const std::string board : {"9by6", "9x", "x6", "2x6", "9x6x2", "9x60000", "9x6.5"}) {
    expect_refused(calibrate("stereo --board " + board + " --square-mm 25" + rest), 2,
                   "--board expects the board's inner corners as COLUMNSxROWS");
  }
  for (const std::string square : {"0", "-25", "abc", "2000", "nan"}) {
    expect_refused(calibrate("stereo --board 9x6 --square-mm " + square + rest), 2, "--square-mm");
  }
}

TEST_F(CalibrateCommand, RefusesAnUnknownRigAndAMissingFolder) {
  expect_refused(calibrate("stereo --board 9x6 --square-mm 25 --rig no_such_rig --images " +
                           views() + " --out " + out()),
                 2, "no_such_rig");
  expect_refused(calibrate("stereo --board 9x6 --square-mm 25 --rig cambio --images " + views() +
                           "/missing --out " + out()),
                 2, "--images: '" + views() + "/missing' is not a directory");
}

TEST_F(CalibrateCommand, NamesUnpairedImagesAndImagesOfTheWrongSize) {
  write_grey("left01.png", 640, 480);
  write_grey("right01.png", 640, 480);
  write_grey("left02.png", 640, 480);
  const std::string line =
      "stereo --board 9x6 --square-mm 25 --rig cambio --images " + views() + " --out " + out();
  expect_refused(calibrate(line), 2, "left02.png has no right02.*");
  write_grey("right02.png", 320, 240);
  expect_refused(calibrate(line), 2,
                 "right02.png' is 320x240 px, expected the rig's 640x480 of camera 'right_eye'");
}

TEST_F(CalibrateCommand, FailsWithTooFewUsableViewsNamingThoseRefused) {
  const TrueStereoPair pair = true_stereo_pair();
  write_rendered_views(pair, TrueBoard{}, board_poses(pair, TrueBoard{}, 5), directory_ / "views");
  write_grey("left06.png", 640, 480);  // No board in either image.
  write_grey("right06.png", 640, 480);
  const CommandResult result = calibrate(
      "stereo --board 9x6 --square-mm 25 --rig cambio --images " + views() + " --out " + out());
  expect_refused(result, 1, "refused view 06: no 9x6 board found in left06.png and right06.png");
  EXPECT_NE(result.output.find("5 views have the board in both images; at least 6 are needed"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(std::filesystem::exists(directory_ / "out" / "camera_calibration.yaml"));
}

}  // namespace
}  // namespace cambio::testing
