// apps/image_files.*: the header reader and decode_image, which `cambio perceive` reads its
// images with and tests/fuzz/fuzz_image_read.cpp feeds arbitrary bytes.
#include "image_files.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace cambio::app {
namespace {

std::vector<std::uint8_t> bytes_of(const std::string& text) {
  return {text.begin(), text.end()};
}

std::vector<std::uint8_t> encoded(const cv::Mat& image, const std::string& extension,
                                  const std::vector<int>& parameters = {}) {
  std::vector<std::uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(extension, image, bytes, parameters));
  return bytes;
}

cv::Mat random_image(int width, int height, int type) {
  cv::Mat image(height, width, type);
  cv::randu(image, 0, CV_MAT_DEPTH(type) == CV_16U ? 65536 : 256);
  return image;
}

/// The ImageFileError message of decoding `bytes`, or "accepted".
std::string refusal(const std::vector<std::uint8_t>& bytes) {
  try {
    (void)decode_image(bytes, "in.img", hal::PixelFormat::kGrey8);
  } catch (const ImageFileError& error) {
    return error.what();
  }
  return "accepted";
}

TEST(ImageFilesTest, AnRgbImageIsEncodedAsPngWithItsChannelsInPlace) {
  // Every pixel different in each channel; OpenCV decodes PNG to BGR.
  hal::Image image(7, 5, hal::PixelFormat::kRgb8);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    image.pixels[i] = static_cast<std::uint8_t>(i * 7 % 251);
  }
  const std::vector<std::uint8_t> png = encode_png(image);
  const cv::Mat decoded = cv::imdecode(png, cv::IMREAD_UNCHANGED);
  ASSERT_EQ(decoded.type(), CV_8UC3);
  ASSERT_EQ(decoded.cols, 7);
  ASSERT_EQ(decoded.rows, 5);
  for (int y = 0; y < 5; ++y) {
    for (int x = 0; x < 7; ++x) {
      const cv::Vec3b bgr = decoded.at<cv::Vec3b>(y, x);
      const std::uint8_t* rgb = image.row(y) + 3 * x;
      EXPECT_EQ(bgr[0], rgb[2]) << x << "," << y;
      EXPECT_EQ(bgr[1], rgb[1]) << x << "," << y;
      EXPECT_EQ(bgr[2], rgb[0]) << x << "," << y;
    }
  }
}

TEST(ImageFilesTest, HeadersGiveTheSizeOfEveryContainerRead) {
  const cv::Mat grey = random_image(17, 12, CV_8U);
  const cv::Mat colour = random_image(7, 9, CV_8UC3);
  struct Case {
    std::vector<std::uint8_t> bytes;
    ImageContainer container;
    int width, height;
  };
  const std::vector<Case> cases = {
      {encoded(grey, ".png"), ImageContainer::kPng, 17, 12},
      {encoded(colour, ".jpg"), ImageContainer::kJpeg, 7, 9},
      {encoded(colour, ".jpg", {cv::IMWRITE_JPEG_PROGRESSIVE, 1}), ImageContainer::kJpeg, 7, 9},
      {encoded(grey, ".pgm"), ImageContainer::kPnm, 17, 12},
      {encoded(colour, ".ppm"), ImageContainer::kPnm, 7, 9},
      {encoded(grey, ".pgm", {cv::IMWRITE_PXM_BINARY, 0}), ImageContainer::kPnm, 17, 12},
      {bytes_of("P5 # a comment\n3\t# another\n 2 255\n\1\2\3\4\5\6"), ImageContainer::kPnm, 3, 2},
  };
  for (const auto& c : cases) {
    const auto header = read_image_header(c.bytes);
    ASSERT_TRUE(header.has_value());
    EXPECT_EQ(header->container, c.container);
    EXPECT_EQ(header->width_px, c.width);
    EXPECT_EQ(header->height_px, c.height);
    const hal::Image image = decode_image(c.bytes, "in", hal::PixelFormat::kGrey8);
    EXPECT_EQ(image.width_px, c.width);
    EXPECT_EQ(image.height_px, c.height);
  }
}

// Every prefix of a valid file is read without reading past its end (ASan builds check the
// bounds): it has no header or the whole file's, and decoding it is refused or gives the image.
TEST(ImageFilesTest, HeadersCutShortAreNoHeadersOrTheSame) {
  for (const auto& bytes :
       {encoded(random_image(5, 4, CV_8U), ".png"), encoded(random_image(5, 4, CV_8UC3), ".jpg"),
        bytes_of("P6\n5 4\n255\n" + std::string(60, 'x'))}) {
    for (std::size_t size = 0; size < bytes.size(); ++size) {
      const std::vector<std::uint8_t> prefix(bytes.begin(), bytes.begin() + size);
      const auto header = read_image_header(prefix);
      if (size < 8) {
        EXPECT_FALSE(header.has_value()) << size;
      }
      if (header) {
        EXPECT_EQ(header->width_px, 5) << size;
        EXPECT_EQ(header->height_px, 4) << size;
      }
      const std::string outcome = refusal(prefix);
      EXPECT_TRUE(outcome == "accepted" || outcome.starts_with("in.img: ")) << outcome;
    }
  }
}

TEST(ImageFilesTest, SixteenBitSamplesAreScaledToEightBits) {
  cv::Mat deep(2, 2, CV_16U, cv::Scalar(65535));
  deep.at<std::uint16_t>(0, 0) = 257 * 10;
  const hal::Image image = decode_image(encoded(deep, ".png"), "deep", hal::PixelFormat::kGrey8);
  EXPECT_EQ(image.pixels[0], 10);
  EXPECT_EQ(image.pixels[1], 255);
}

TEST(ImageFilesTest, ImagesDeclaringTooManyPixelsAreRefusedBeforeDecoding) {
  EXPECT_NE(refusal(bytes_of("P5\n16385 1\n255\n")).find("in.img: declares a 16385x1 px image"),
            std::string::npos);
  EXPECT_NE(refusal(bytes_of("P5\n9000 9000\n255\n")).find("declares a 9000x9000 px image"),
            std::string::npos)
      << "81 Mpx, past the 64 Mpx bound";
  EXPECT_NE(refusal(bytes_of("P5\n99999999999999999999 2\n255\n")).find("declares a"),
            std::string::npos);
  EXPECT_NE(refusal(bytes_of("P5\n0 2\n255\n")).find("declares an empty image"), std::string::npos);
  // A JPEG whose frame header declares 65535x65535 behind an application segment.
  const auto jpeg =
      bytes_of(std::string("\xFF\xD8\xFF\xE0\x00\x04..\xFF\xC0\x00\x0B\x08\xFF\xFF"
                           "\xFF\xFF\x01\x01\x11\x00",
                           21));
  EXPECT_NE(refusal(jpeg).find("declares a 65535x65535 px image"), std::string::npos)
      << refusal(jpeg);
}

TEST(ImageFilesTest, OtherContainersAndDamagedFilesAreRefusedWithTheName) {
  EXPECT_EQ(refusal({}), "in.img: empty file");
  EXPECT_NE(refusal(encoded(random_image(4, 4, CV_8U), ".bmp")).find("in.img: not an image"),
            std::string::npos);
  auto png = encoded(random_image(40, 40, CV_8U), ".png");
  png.resize(png.size() / 2);
  EXPECT_NE(refusal(png).find("in.img: a damaged PNG file"), std::string::npos);
}

// Regression, found by tests/fuzz/fuzz_image_read.cpp: FF D8 without OpenCV's JPEG signature
// (FF D8 FF), and "DICM" at byte 128. OpenCV handed it to GDCM's DICOM reader, which aborted
// the process on an assertion. A container is now recognised only by the signature OpenCV's
// decoder for it checks.
TEST(ImageFilesTest, BytesOpenCvWouldGiveToAnotherDecoderAreRefused) {
  const std::string crash(
      "\xFF\xD8\x8A\xFF\xC0\x00\x22\x00\x02\x01\x04\x00\x00\x00\x00\x00\x00\x00\x00\x00"
      "\x00\x00\x00\x00\x00\x00\x00\x75\x73\x77\x2F\x6C\x69\x06\x00\x00\xFF\x01\x9F\x96"
      "\x7C\x6C\x69\x06\x00\x00\xFF\x01\x9F\x96\x7C\xCD\x61\x23\x24\x24\x24\x24\x24\x24"
      "\x24\x24\x24\x24\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44"
      "\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44"
      "\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x44\x24\x24\x24\x24"
      "\x24\x44\x49\x43\x4D\x03\x02\x04\x44\x49\x43\x4D\x0B\x00",
      134);
  const std::vector<std::uint8_t> bytes(crash.begin(), crash.end());
  EXPECT_FALSE(read_image_header(bytes).has_value());
  EXPECT_NE(refusal(bytes).find("in.img: not an image this program reads"), std::string::npos);
  // A JPEG with a byte between SOI and the next marker: libjpeg would read it, OpenCV would not
  // take it for a JPEG.
  auto jpeg = encoded(random_image(8, 8, CV_8U), ".jpg");
  jpeg.insert(jpeg.begin() + 2, 0x00);
  EXPECT_FALSE(read_image_header(jpeg).has_value());
  // Found by fuzz_image_read in CI: a comment glued to a size. This reader took the width for
  // 5554, OpenCV's for 5554688, which asked for 2.5 GB.
  const std::string glued("P6\n\n5554#76666\n688\n6", 20);
  const std::vector<std::uint8_t> pnm(glued.begin(), glued.end());
  EXPECT_FALSE(read_image_header(pnm).has_value());
  EXPECT_NE(refusal(pnm).find("in.img: not an image this program reads"), std::string::npos);
}

}  // namespace
}  // namespace cambio::app
