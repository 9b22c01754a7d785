// The PNG, JPEG and PGM/PPM decoders behind decode_image (libpng and libjpeg driven directly)
// against OpenCV's imgcodecs as the peer: the same files decode to the same pixels, grey or
// colour, 8 or 16 bit, and a JPEG's EXIF orientation turns it as OpenCV turns it.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "exif_orientation.hpp"
#include "image_files.hpp"

namespace cambio::app {
namespace {

std::vector<std::uint8_t> encoded(const cv::Mat& image, const std::string& extension,
                                  const std::vector<int>& parameters = {}) {
  std::vector<std::uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(extension, image, bytes, parameters));
  return bytes;
}

// Gradients (a different one per channel) with some noise: JPEG keeps them close, and every
// sample value is met.
cv::Mat test_image(int width, int height, int type) {
  const int channels = CV_MAT_CN(type);
  const double top = CV_MAT_DEPTH(type) == CV_16U ? 65535.0 : 255.0;
  cv::Mat ramp(height, width, CV_64FC(channels));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < channels; ++c) {
        ramp.ptr<double>(y)[x * channels + c] = top * ((x * (3 + c) + y * (5 - c)) % 64) / 63.0;
      }
    }
  }
  cv::Mat noise(height, width, CV_64FC(channels));
  cv::randu(noise, 0.0, top);
  cv::Mat image;
  cv::Mat(0.8 * ramp + 0.2 * noise).convertTo(image, type);
  return image;
}

// What OpenCV decodes `bytes` to, as the pixels decode_image gives for `format`: 16 bit scaled
// by 1/257, colour turned grey or from BGR to RGB.
cv::Mat opencv_reads(const std::vector<std::uint8_t>& bytes, hal::PixelFormat format) {
  cv::Mat raw = cv::imdecode(bytes, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  if (raw.depth() == CV_16U) raw.convertTo(raw, CV_8U, 1.0 / 257.0);
  cv::Mat converted;
  const bool grey = format == hal::PixelFormat::kGrey8;
  switch (raw.channels()) {
    case 1:
      converted = grey ? raw : cv::Mat();
      if (!grey) cv::cvtColor(raw, converted, cv::COLOR_GRAY2RGB);
      break;
    case 3:
      cv::cvtColor(raw, converted, grey ? cv::COLOR_BGR2GRAY : cv::COLOR_BGR2RGB);
      break;
    default:
      cv::cvtColor(raw, converted, grey ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGRA2RGB);
      break;
  }
  return converted;
}

void expect_same_pixels(const std::vector<std::uint8_t>& bytes, hal::PixelFormat format,
                        const std::string& what) {
  const cv::Mat peer = opencv_reads(bytes, format);
  const hal::Image image = decode_image(bytes, what, format);
  ASSERT_EQ(image.width_px, peer.cols) << what;
  ASSERT_EQ(image.height_px, peer.rows) << what;
  int differing = 0;
  for (int y = 0; y < peer.rows; ++y) {
    for (std::size_t i = 0; i < image.stride_bytes(); ++i) {
      differing += image.row(y)[i] != peer.ptr<std::uint8_t>(y)[i] ? 1 : 0;
    }
  }
  EXPECT_EQ(differing, 0) << what << (format == hal::PixelFormat::kGrey8 ? " grey" : " RGB");
}

TEST(ImageDecodersTest, PngFilesDecodeAsOpenCvDecodesThem) {
  const std::vector<std::pair<std::string, cv::Mat>> files = {
      {"grey", test_image(31, 17, CV_8UC1)},    {"BGR", test_image(31, 17, CV_8UC3)},
      {"BGRA", test_image(31, 17, CV_8UC4)},    {"grey 16", test_image(13, 11, CV_16UC1)},
      {"BGR 16", test_image(13, 11, CV_16UC3)}, {"BGRA 16", test_image(13, 11, CV_16UC4)},
  };
  for (const auto& [what, mat] : files) {
    for (const auto format : {hal::PixelFormat::kGrey8, hal::PixelFormat::kRgb8}) {
      expect_same_pixels(encoded(mat, ".png"), format, "PNG " + what);
    }
  }
  // One bit per pixel.
  const cv::Mat bilevel = test_image(19, 7, CV_8UC1) > 128;
  expect_same_pixels(encoded(bilevel, ".png", {cv::IMWRITE_PNG_BILEVEL, 1}),
                     hal::PixelFormat::kGrey8, "PNG 1 bit");
}

// Two kinds of PNG OpenCV cannot write, kept as fuzzing seeds (tests/fuzz/seeds/image_read/, made
// by hand with zlib): a 3x3 grey image interlaced (Adam7) with the samples 10, 20, ... 90 in
// reading order, and a 2x2 palette image (red, green / blue, red) whose tRNS chunk is dropped.
TEST(ImageDecodersTest, InterlacedAndPalettePngsDecodeToTheirSamples) {
  const std::string seeds = CAMBIO_IMAGE_SEEDS_DIR;
  const hal::Image interlaced =
      read_image_file(seeds + "/interlaced.png", hal::PixelFormat::kGrey8);
  EXPECT_EQ(interlaced.pixels, (std::vector<std::uint8_t>{10, 20, 30, 40, 50, 60, 70, 80, 90}));
  const hal::Image palette = read_image_file(seeds + "/palette_trns.png", hal::PixelFormat::kRgb8);
  EXPECT_EQ(palette.pixels,
            (std::vector<std::uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 0, 0}));
}

TEST(ImageDecodersTest, PngFilesWrittenHereAreReadBackByOpenCvUnchanged) {
  hal::Image grey(23, 9, hal::PixelFormat::kGrey8);
  for (std::size_t i = 0; i < grey.pixels.size(); ++i) grey.pixels[i] = (i * 37) % 256;
  const cv::Mat grey_back = cv::imdecode(encode_png(grey), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(grey_back.type(), CV_8UC1);
  EXPECT_EQ(cv::countNonZero(grey_back != cv::Mat(9, 23, CV_8UC1, grey.pixels.data())), 0);
  std::vector<std::uint16_t> depth_mm(23 * 9);
  for (std::size_t i = 0; i < depth_mm.size(); ++i) depth_mm[i] = (i * 2731) % 65536;
  const cv::Mat depth_back = cv::imdecode(encode_png16(depth_mm, 23, 9), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(depth_back.type(), CV_16UC1);
  EXPECT_EQ(cv::countNonZero(depth_back != cv::Mat(9, 23, CV_16UC1, depth_mm.data())), 0);
  EXPECT_THROW(encode_png16(depth_mm, 22, 9), ImageFileError);
}

TEST(ImageDecodersTest, JpegFilesDecodeAsOpenCvDecodesThem) {
  for (const bool progressive : {false, true}) {
    for (const int type : {CV_8UC1, CV_8UC3}) {
      const auto bytes = encoded(test_image(45, 29, type), ".jpg",
                                 {cv::IMWRITE_JPEG_PROGRESSIVE, progressive ? 1 : 0});
      for (const auto format : {hal::PixelFormat::kGrey8, hal::PixelFormat::kRgb8}) {
        expect_same_pixels(bytes, format,
                           std::string(progressive ? "progressive " : "baseline ") +
                               (type == CV_8UC1 ? "grey" : "colour") + " JPEG");
      }
    }
  }
}

// An APP1 segment with an EXIF IFD0 holding only the Orientation tag, in either byte order.
std::vector<std::uint8_t> exif_app1(int orientation, bool big_endian) {
  std::vector<std::uint8_t> tiff = big_endian
                                       ? std::vector<std::uint8_t>{'M', 'M', 0, 42, 0, 0, 0, 8}
                                       : std::vector<std::uint8_t>{'I', 'I', 42, 0, 8, 0, 0, 0};
  const auto put16 = [&](int value) {
    const auto high = static_cast<std::uint8_t>(value >> 8);
    const auto low = static_cast<std::uint8_t>(value & 0xFF);
    tiff.push_back(big_endian ? high : low);
    tiff.push_back(big_endian ? low : high);
  };
  const auto put32 = [&](int value) {
    if (big_endian) put16(value >> 16);
    put16(value & 0xFFFF);
    if (!big_endian) put16(value >> 16);
  };
  put16(1);       // one entry
  put16(0x0112);  // Orientation
  put16(3);       // SHORT
  put32(1);       // one value
  put16(orientation);
  put16(0);
  put32(0);  // no next IFD
  std::vector<std::uint8_t> payload = {'E', 'x', 'i', 'f', 0, 0};
  payload.insert(payload.end(), tiff.begin(), tiff.end());
  std::vector<std::uint8_t> segment = {0xFF, 0xE1,
                                       static_cast<std::uint8_t>((payload.size() + 2) >> 8),
                                       static_cast<std::uint8_t>((payload.size() + 2) & 0xFF)};
  segment.insert(segment.end(), payload.begin(), payload.end());
  return segment;
}

TEST(ImageDecodersTest, JpegExifOrientationTurnsTheImageAsOpenCvTurnsIt) {
  const auto plain = encoded(test_image(24, 15, CV_8UC3), ".jpg", {cv::IMWRITE_JPEG_QUALITY, 98});
  for (const bool big_endian : {false, true}) {
    for (int orientation = 1; orientation <= 8; ++orientation) {
      std::vector<std::uint8_t> bytes = plain;
      const auto app1 = exif_app1(orientation, big_endian);
      bytes.insert(bytes.begin() + 2, app1.begin(), app1.end());
      const auto header = read_image_header(bytes);
      ASSERT_TRUE(header.has_value());
      EXPECT_EQ(header->width_px, 24);
      expect_same_pixels(
          bytes, hal::PixelFormat::kRgb8,
          "orientation " + std::to_string(orientation) + (big_endian ? " MM" : " II"));
      const hal::Image image = decode_image(bytes, "turned", hal::PixelFormat::kGrey8);
      EXPECT_EQ(image.width_px, orientation >= 5 ? 15 : 24) << orientation;
    }
  }
}

TEST(ImageDecodersTest, MalformedExifLeavesTheImageAsStored) {
  auto app1 = exif_app1(6, false);
  const std::vector<std::uint8_t> payload(app1.begin() + 4, app1.end());
  EXPECT_EQ(read_exif_orientation(payload), 6);
  for (std::size_t size = 0; size < payload.size(); ++size) {
    const int orientation = read_exif_orientation({payload.data(), size});
    EXPECT_TRUE(orientation == 1 || orientation == 6) << size;
  }
  auto out_of_range = exif_app1(9, true);
  EXPECT_EQ(read_exif_orientation({out_of_range.data() + 4, out_of_range.size() - 4}), 1);
  auto long_type = payload;
  long_type[6 + 8 + 2 + 2] = 4;  // LONG instead of SHORT (little-endian type field)
  EXPECT_EQ(read_exif_orientation(long_type), 1);
  auto far_ifd = payload;
  far_ifd[6 + 4] = 0xF0;  // IFD0 beyond the segment
  EXPECT_EQ(read_exif_orientation(far_ifd), 1);
}

TEST(ImageDecodersTest, AJpegCutShortIsDamagedNotFilledWithGrey) {
  auto bytes = encoded(test_image(64, 48, CV_8UC3), ".jpg");
  bytes.resize(bytes.size() * 2 / 3);
  try {
    (void)decode_image(bytes, "cut.jpg", hal::PixelFormat::kGrey8);
    FAIL() << "a JPEG cut to two thirds was accepted";
  } catch (const ImageFileError& error) {
    EXPECT_EQ(std::string(error.what()),
              "cut.jpg: a damaged JPEG file (its pixels cannot be decoded: the file ends before "
              "its last scan)");
  }
}

TEST(ImageDecodersTest, PgmAndPpmFilesDecodeAsOpenCvDecodesThem) {
  for (const int type : {CV_8UC1, CV_8UC3, CV_16UC1, CV_16UC3}) {
    const cv::Mat mat = test_image(21, 8, type);
    const std::string extension = CV_MAT_CN(type) == 1 ? ".pgm" : ".ppm";
    for (const int binary : {1, 0}) {
      const auto bytes = encoded(mat, extension, {cv::IMWRITE_PXM_BINARY, binary});
      for (const auto format : {hal::PixelFormat::kGrey8, hal::PixelFormat::kRgb8}) {
        expect_same_pixels(bytes, format,
                           extension + (binary != 0 ? " binary " : " text ") +
                               std::to_string(CV_ELEM_SIZE1(type) * 8) + " bit");
      }
    }
  }
}

TEST(ImageDecodersTest, PgmSamplesAreScaledFromTheLargestValueAndCheckedAgainstIt) {
  const auto bytes = [](const std::string& text) {
    return std::vector<std::uint8_t>(text.begin(), text.end());
  };
  // 4-bit samples: v * 255 / 15 = 17 v.
  const hal::Image four_bit =
      decode_image(bytes("P2\n4 1\n15\n0 1 14 15\n"), "four.pgm", hal::PixelFormat::kGrey8);
  EXPECT_EQ(four_bit.pixels, (std::vector<std::uint8_t>{0, 17, 238, 255}));
  // 10-bit binary samples, big-endian: round(v * 255 / 1023).
  const hal::Image ten_bit =
      decode_image(bytes(std::string("P5\n3 1\n1023\n\x00\x00\x02\x00\x03\xFF", 18)), "ten.pgm",
                   hal::PixelFormat::kGrey8);
  EXPECT_EQ(ten_bit.pixels, (std::vector<std::uint8_t>{0, 128, 255}));
  const auto refusal = [&](const std::string& text) {
    try {
      (void)decode_image(bytes(text), "in.pgm", hal::PixelFormat::kGrey8);
    } catch (const ImageFileError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refusal("P2\n2 1\n15\n3 16\n"),
            "in.pgm: a damaged PGM/PPM file (its pixels cannot be decoded: sample 1 is above the "
            "largest value 15)");
  EXPECT_EQ(refusal("P2\n2 1\n15\n3\n"),
            "in.pgm: a damaged PGM/PPM file (its pixels cannot be decoded: the file ends before "
            "its last sample)");
  EXPECT_EQ(refusal("P2\n2 1\n15\n3 x\n"),
            "in.pgm: a damaged PGM/PPM file (its pixels cannot be decoded: sample 1 is not a "
            "number)");
  EXPECT_EQ(refusal("P5\n2 2\n255\nabc"),
            "in.pgm: a damaged PGM/PPM file (its pixels cannot be decoded: the file ends before "
            "its last sample)");
  EXPECT_EQ(refusal(std::string("P5\n2 1\n100\n\x05\x65", 14)),
            "in.pgm: a damaged PGM/PPM file (its pixels cannot be decoded: sample 1 is 101, "
            "above the largest value 100)");
}

}  // namespace
}  // namespace cambio::app
