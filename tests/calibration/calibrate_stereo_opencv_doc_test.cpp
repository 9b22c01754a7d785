// `cambio calibrate stereo` on real photographs: the 9x6 chessboard pairs OpenCV ships in
// Debian's opencv-doc (examples/data/left01.jpg ... right14.jpg, 640x480, 13 pairs). The package
// is fetched with `apt-get download` (never installed) and only those images are extracted, into
// a cache in the build tree; where the download fails the test says so and exits 77 (ctest's
// SKIP_RETURN_CODE). OpenCV's stereo_calib sample reports an RMS of about 0.4-0.5 px on them.
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <regex>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "../apps/run_cambio.hpp"

namespace cambio::testing {
namespace {

constexpr int kSkip = 77;
const std::filesystem::path kCache =
    std::filesystem::path(CAMBIO_BINARY_DIR) / "test-data" / "opencv-doc-chessboard";
constexpr const char* kDataInPackage = "./usr/share/doc/opencv-doc/examples/data/";

bool cached() {
  return std::filesystem::exists(kCache / "right14.jpg");
}

/// Downloads opencv-doc into a scratch folder and extracts the left/right images into the cache;
/// the reason when it cannot.
std::string fetch() {
  const auto scratch =
      std::filesystem::temp_directory_path() / ("cambio_opencv_doc_" + std::to_string(::getpid()));
  std::filesystem::create_directories(scratch);
  std::filesystem::create_directories(kCache);
  const std::string quoted = "'" + scratch.string() + "'";
  const CommandResult download = run_shell("cd " + quoted + " && apt-get download opencv-doc 2>&1");
  std::string problem;
  if (download.exit_code != 0) {
    problem = "apt-get download opencv-doc failed: " + download.output;
  } else {
    const CommandResult extract = run_shell(
        "cd " + quoted + " && dpkg-deb --fsys-tarfile opencv-doc_*.deb | tar -x --wildcards '" +
        kDataInPackage + "left[0-9]*.jpg' '" + kDataInPackage + "right[0-9]*.jpg' && cp " +
        kDataInPackage + "*.jpg '" + kCache.string() + "/' 2>&1");
    if (extract.exit_code != 0) problem = "extracting the images failed: " + extract.output;
  }
  std::filesystem::remove_all(scratch);
  return problem;
}

TEST(OpenCvDocPairs, EveryFindableViewIsUsedTheOthersNamedAndTheRmsIsSubPixel) {
  const auto out = std::filesystem::temp_directory_path() /
                   ("cambio_opencv_doc_out_" + std::to_string(::getpid()));
  const CommandResult result =
      run_cambio("calibrate stereo --images '" + kCache.string() +
                 "' --board 9x6 --square-mm 25 --rig cambio --out '" + out.string() + "'");
  std::cout << result.output;
  ASSERT_EQ(result.exit_code, 0) << result.output;

  // Which views have the board in both images, by OpenCV's detector alone (no refinement).
  int views = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kCache)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with("left")) continue;
    ++views;
    const std::string id = name.substr(4, name.size() - 8);
    bool both = true;
    for (const std::string side : {"left", "right"}) {
      std::vector<cv::Point2f> corners;
      both = both && cv::findChessboardCorners(
                         cv::imread((kCache / (side + id + ".jpg")).string(), cv::IMREAD_GRAYSCALE),
                         cv::Size(9, 6), corners,
                         cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
    }
    std::smatch match;
    if (both) {
      ASSERT_TRUE(
          std::regex_search(result.output, match, std::regex("view " + id + ": RMS ([0-9.]+) px")))
          << "view " << id << " has a findable board but was not used";
      EXPECT_LT(std::stod(match[1]), 1.5) << "view " << id;
    } else {
      EXPECT_NE(result.output.find("refused view " + id + ": no 9x6 board found in "),
                std::string::npos)
          << "view " << id << " has no findable board but is not named";
    }
  }
  EXPECT_EQ(views, 13) << "opencv-doc 4.6 ships 13 pairs (01-09, 11-14)";
  std::smatch match;
  ASSERT_TRUE(std::regex_search(result.output, match, std::regex("overall: RMS ([0-9.]+) px")));
  EXPECT_GT(std::stod(match[1]), 0.05) << "real photographs cannot fit to the noise floor";
  EXPECT_LT(std::stod(match[1]), 1.0);
  EXPECT_TRUE(std::filesystem::exists(out / "camera_calibration.yaml"));
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace cambio::testing

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (!cambio::testing::cached()) {
    const std::string problem = cambio::testing::fetch();
    if (!problem.empty()) {
      std::cout << "SKIPPED: " << problem << "\n";
      return cambio::testing::kSkip;
    }
  }
  return RUN_ALL_TESTS();
}
