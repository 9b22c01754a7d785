// Bad input to `cambio` exits 2 with a message that names what and where, never 1 with a
// library's text: numbers on the command line, image files, output directories.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "run_cambio.hpp"

namespace cambio {
namespace {

using testing::run_cambio;

struct Case {
  std::string arguments;
  std::string expected;  ///< A part of the message.
};

void expect_bad_input(const std::vector<Case>& cases) {
  for (const auto& c : cases) {
    const auto result = run_cambio(c.arguments);
    EXPECT_EQ(result.exit_code, 2) << c.arguments << "\n" << result.output;
    EXPECT_NE(result.output.find(c.expected), std::string::npos)
        << c.arguments << ": expected '" << c.expected << "' in\n"
        << result.output;
  }
}

// Every numeric option of every command, each just outside its range or not a number at all.
// Before, --repeats 0 became 5, --repeats 2147483648 ended in vector::reserve (exit 1), --cpu -5
// and --priority 4294967376 (80 after wrapping) were accepted, --duration-s 1e300 ran forever.
TEST(BadInputTest, EveryNumericOptionIsRangeChecked) {
  expect_bad_input({
      {"perception-bench --repeats 0", "'--repeats' expects a whole number in [5, 100000]"},
      {"perception-bench --repeats 2147483648", "got '2147483648'"},
      {"loop-bench --cpu -5", "'--cpu' expects a whole number in [-1, "},
      {"loop-bench --priority 4294967376", "'--priority' expects a whole number in [0, 99]"},
      {"loop-bench --rate-hz 0", "'--rate-hz' expects a number in (0, 100000]"},
      {"loop-bench --rate-hz 0x10", "'--rate-hz' expects a number in (0, 100000]"},
      {"loop-bench --duration-s 1e300", "'--duration-s' expects a number in (0, 36000]"},
      {"loop-bench --duration-s nan", "'--duration-s' expects a number in (0, 36000]"},
      {"sim-bench --seconds 0", "'--seconds' expects a number in (0, 3600]"},
      {"sim-bench --width 4097 --height 480", "'--width' expects a whole number in [16, 4096]"},
      {"sim-bench --width 640 --height 15", "'--height' expects a whole number in [16, 4096]"},
  });
}

std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::path(CAMBIO_BINARY_DIR) / "test_output" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// A random-texture grey PNG of `width` x `height` px.
std::filesystem::path textured_png(const std::filesystem::path& dir, int width, int height) {
  cv::Mat image(height, width, CV_8U);
  cv::randu(image, 0, 256);
  const auto path = dir / (std::to_string(width) + "x" + std::to_string(height) + ".png");
  EXPECT_TRUE(cv::imwrite(path.string(), image));
  return path;
}

std::filesystem::path file_with(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

/// A PNG signature and IHDR declaring `width` x `height` (grey, 8 bit) with no pixel data: what a
/// decompression bomb shows before its few hundred kilobytes of zeros.
std::string png_header(std::uint32_t width, std::uint32_t height) {
  std::string bytes("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 16);
  for (const std::uint32_t side : {width, height}) {
    for (int shift = 24; shift >= 0; shift -= 8) bytes += static_cast<char>((side >> shift) & 0xFF);
  }
  return bytes + std::string("\x08\0\0\0\0\0\0\0\0", 9);
}

std::string perceive(const std::filesystem::path& image, const std::filesystem::path& out) {
  return "perceive --left '" + image.string() + "' --right '" + image.string() + "' --out '" +
         out.string() + "'";
}

// Before: a 142-byte file aborted the program (134) in GDCM, 5000x1 ended in OpenCV's
// "inv_scale_x > 0" (exit 1), 1x500 and 1x1 were measured (on the images' clamped borders), a PGM
// declaring 60000x60000 ended in OpenCV's validateInputImageSize (exit 1), a PNG declaring
// 30000x30000 was decoded into 900 MB.
TEST(BadInputTest, PerceiveRefusesImagesItCannotMeasureWithTheFileName) {
  const auto dir = fresh_dir("bad_images");
  const auto out = dir / "out";
  const std::vector<std::pair<std::filesystem::path, std::string>> cases = {
      {textured_png(dir, 1, 500), "are 1x500 px; the SSM needs images of at least 40x40 px"},
      {textured_png(dir, 5000, 1), "are 5000x1 px; the SSM needs images of at least 40x40 px"},
      {textured_png(dir, 1, 1), "are 1x1 px"},
      {textured_png(dir, 39, 40), "are 39x40 px"},
      {file_with(dir / "empty.png", ""), "empty.png: empty file"},
      {file_with(dir / "text.png", "not an image at all"), "text.png: not an image this program"},
      {file_with(dir / "bomb.png", png_header(30000, 30000)),
       "bomb.png: declares a 30000x30000 px image; images are read up to 16384 px a side"},
      {file_with(dir / "wide.png", png_header(70000, 1)), "declares a 70000x1 px image"},
      {file_with(dir / "cut.png", png_header(64, 64)), "cut.png: a damaged PNG file"},
      {file_with(dir / "huge.pgm", "P5\n60000 60000\n255\n"),
       "huge.pgm: declares a 60000x60000 px image"},
      {file_with(dir / "short.pgm", "P5\n64 64\n255\nabc"), "short.pgm: a damaged PGM/PPM file"},
      // "DICM" at byte 128 took OpenCV to GDCM's DICOM reader, whose assertion aborted (134).
      {file_with(dir / "dicom.png",
                 std::string(128, '\0') + "DICM" + std::string("\x02\0\x10\0UI\0\0\0\0", 10)),
       "dicom.png: not an image this program reads"},
      {dir, "a directory, not an image file"},
  };
  for (const auto& [image, expected] : cases) {
    const auto result = run_cambio(perceive(image, out));
    EXPECT_EQ(result.exit_code, 2) << image << "\n" << result.output;
    EXPECT_NE(result.output.find(expected), std::string::npos)
        << image << ": expected '" << expected << "' in\n"
        << result.output;
    EXPECT_FALSE(std::filesystem::exists(out / "contact_sheet.png")) << image;
    EXPECT_EQ(result.output.find("OpenCV("), std::string::npos) << "library text:\n"
                                                                << result.output;
  }
}

// The contact sheet is for people: tall or wide images are fitted into a bounded canvas. Before,
// a 40x5000 pair made a 1182x73000 px sheet (a 1x500 pair 1182x292046 px, 3.1 GB of memory).
TEST(BadInputTest, PerceiveFitsTheContactSheetOfThinImagesIntoABoundedCanvas) {
  const auto dir = fresh_dir("thin_images");
  for (const auto& [width, height] : {std::pair{40, 5000}, std::pair{5000, 40}}) {
    const auto image = textured_png(dir, width, height);
    const auto out = dir / ("out_" + std::to_string(width));
    const auto result = run_cambio(perceive(image, out));
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const cv::Mat sheet = cv::imread((out / "contact_sheet.png").string());
    ASSERT_FALSE(sheet.empty());
    EXPECT_LE(sheet.cols, 1600) << width << "x" << height;
    EXPECT_LE(sheet.rows, 2400) << width << "x" << height;
    EXPECT_LT(std::filesystem::file_size(out / "contact_sheet.png"), 8u << 20);
  }
}

TEST(BadInputTest, PerceiveRefusesAnOutputDirectoryItCannotWriteBeforeAnyWork) {
  const auto dir = fresh_dir("unwritable_out");
  const auto image = textured_png(dir, 64, 64);
  const auto blocker = file_with(dir / "a_file", "x");
  for (const auto& [out, why] : {std::pair{blocker, std::string(" exists and is not a directory")},
                                 std::pair{blocker / "below", std::string(": cannot create")}}) {
    const auto result = run_cambio(perceive(image, out));
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_NE(result.output.find("'" + out.string() + "'" + why), std::string::npos)
        << result.output;
  }
}

// Scenes and cameras MuJoCo cannot build were reported as translation bugs with MuJoCo's text
// (exit 1): 'yaxis too small', 'Stack overflow', 'Offscreen framebuffer is not complete'.
TEST(BadInputTest, RenderRefusesScenesAndCamerasTheSimCannotBuildNamingTheKey) {
  const auto dir = fresh_dir("bad_scenes");
  const auto out = (dir / "out").string();
  const auto scene =
      file_with(dir / "self.yaml", "overview_camera: {xyz_m: [1, 2, 3], look_at_m: [1, 2, 3]}\n");
  expect_bad_input({
      {"render --scene '" + scene.string() + "' --out '" + out + "'",
       "self.yaml: overview_camera.look_at_m: expected a point other than the camera's own"},
      {"render --scene vergence --out '" + out +
           "' --set cameras.left_eye.width_px=65535 "
           "--set cameras.left_eye.principal_point_px=[32767,239.5]",
       "cameras.left_eye.width_px: expected an integer in [1, 4096]"},
  });
}

TEST(BadInputTest, RenderRefusesAnOutputDirectoryItCannotWriteBeforeAnyWork) {
  const auto dir = fresh_dir("render_unwritable_out");
  const auto blocker = file_with(dir / "a_file", "x");
  expect_bad_input({{"render --scene vergence --out '" + (blocker / "below").string() + "'",
                     "'" + (blocker / "below").string() + "': cannot create"}});
}

// Lines have a length limit and a fault file is a regular file: before, `console < /dev/zero`
// grew to 4.1 GB and exited 0, `--fault-file /dev/zero` to 2.1 GB and injected nothing, and a
// directory as --fault-file exited 0.
TEST(BadInputTest, EndlessLinesAndFaultFilesThatAreNoFilesAreRefused) {
  const std::filesystem::path long_line =
      std::filesystem::temp_directory_path() / "cambio_bad_input_long_line.faults";
  std::ofstream(long_line) << std::string(5000, 'x') << "\n";
  expect_bad_input({
      {"virtual-rig --config pan_tilt --fault-file /tmp", "not a regular file"},
      {"virtual-rig --config pan_tilt --fault-file /dev/zero", "not a regular file"},
      {"virtual-rig --config pan_tilt --fault-file '" + long_line.string() + "'",
       ":1: longer than 4096 characters"},
      {"console firmware_config/experiments/vergence_sphere.yaml --rtf 0 < /dev/zero",
       "input line 1 is longer than 4096 characters"},
  });
}

// --rtf took strtod's whole language ("0x1p3" ran at 8x, " 2" at 2x) where every other number
// option takes decimal text only.
TEST(BadInputTest, TheRealTimeFactorIsADecimalNumberAsEveryOtherOption) {
  const std::string console = "console firmware_config/experiments/vergence_sphere.yaml --rtf ";
  expect_bad_input({
      {console + "0x1p3 < /dev/null", "option '--rtf' expects a number"},
      {console + "' 2' < /dev/null", "option '--rtf' expects a number"},
      {console + "-1 < /dev/null", "option '--rtf' expects a number"},
      {console + "nan < /dev/null", "option '--rtf' expects a number"},
  });
}

// Every malformed --set of `run` and `console` is named, not only the first (they stopped at the
// first before), and nothing starts.
TEST(BadInputTest, RunAndConsoleNameEveryMalformedOverride) {
  for (const std::string command : {"run", "console"}) {
    const auto result = run_cambio(command +
                                   " firmware_config/experiments/vergence_sphere.yaml --set "
                                   "nonsense --set 'alsobad' < /dev/null");
    EXPECT_EQ(result.exit_code, 2) << command << "\n" << result.output;
    EXPECT_NE(result.output.find("found \"nonsense\""), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("found \"alsobad\""), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("2 problems found; nothing was started."), std::string::npos)
        << result.output;
  }
}

// A CAMBIO_CONFIG_DIR that is no directory: before, render said "cannot read the file" without
// naming it and perceive ran on built-in defaults without a word.
TEST(BadInputTest, AConfigDirectoryThatIsNotThereIsNamed) {
  const auto dir = fresh_dir("bad_config_dir");
  const auto image = (dir / "grey.pgm").string();
  std::ofstream(image) << "P5 8 8 255\n" << std::string(64, '\x80');
  for (const std::string& arguments :
       {"render --scene vergence --out '" + (dir / "r").string() + "'",
        "perceive --left '" + image + "' --right '" + image + "' --out '" + (dir / "p").string() +
            "'"}) {
    const auto result = testing::run_shell(
        "cd '" + std::string(CAMBIO_SOURCE_DIR) + "' && CAMBIO_CONFIG_DIR=/nonexistent/cambio '" +
        CAMBIO_BINARY_DIR + "/bin/cambio' " + arguments + " 2>&1");
    EXPECT_EQ(result.exit_code, 2) << arguments << "\n" << result.output;
    EXPECT_NE(result.output.find("CAMBIO_CONFIG_DIR: expected the directory of"), std::string::npos)
        << result.output;
    EXPECT_NE(result.output.find("\"/nonexistent/cambio\": it does not exist"), std::string::npos)
        << result.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "p" / "summary.json")) << arguments;
  }
}

}  // namespace
}  // namespace cambio
