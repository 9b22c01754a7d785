// An MJPEG camera over a fake device (fake_video_device.hpp): the frames a camera sends (JPEGs
// OpenCV encodes here, as a UVC camera's encoder would) decode to what OpenCV's decoder gives,
// grey and colour, with or without Huffman tables; damaged, cut-short and wrongly sized frames
// are dropped and counted; and what the decoding allocates per frame is measured, not assumed.

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "cambio/hal/manual_clock.hpp"
#include "cambio/runtime/allocation_counter.hpp"
#include "cambio/v4l2/mjpeg_decoder.hpp"
#include "cambio/v4l2/v4l2_capture.hpp"
#include "fake_video_device.hpp"

namespace cambio::v4l2 {
namespace {

using test::FakeVideoDevice;

constexpr int kWidth = 48;
constexpr int kHeight = 32;
constexpr std::int64_t kPeriodNs = 33'333'333;

// A colour scene: gradients per channel and noise, so every pixel differs.
cv::Mat scene(int width = kWidth, int height = kHeight, int seed = 1) {
  cv::Mat bgr(height, width, CV_8UC3);
  cv::RNG rng(static_cast<std::uint64_t>(seed));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      bgr.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<std::uint8_t>(x * 5 + rng.uniform(0, 40)),
                                          static_cast<std::uint8_t>(y * 7 + rng.uniform(0, 40)),
                                          static_cast<std::uint8_t>((x + y) * 3));
    }
  }
  return bgr;
}

std::vector<std::uint8_t> jpeg_of(const cv::Mat& bgr) {
  std::vector<std::uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(".jpg", bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, 90}));
  return bytes;
}

// The JPEG without its DHT segments, as most UVC cameras send MJPEG (AVI1): the decoder must
// supply JPEG's standard tables, the ones libjpeg's encoder used.
std::vector<std::uint8_t> without_huffman_tables(const std::vector<std::uint8_t>& jpeg) {
  std::vector<std::uint8_t> out(jpeg.begin(), jpeg.begin() + 2);
  std::size_t i = 2;
  while (i + 4 <= jpeg.size() && jpeg[i] == 0xFF && jpeg[i + 1] != 0xDA) {
    const std::size_t length = (static_cast<std::size_t>(jpeg[i + 2]) << 8) | jpeg[i + 3];
    if (jpeg[i + 1] != 0xC4) out.insert(out.end(), jpeg.begin() + i, jpeg.begin() + i + 2 + length);
    i += 2 + length;
  }
  out.insert(out.end(), jpeg.begin() + i, jpeg.end());
  return out;
}

struct MjpegRig {
  hal::ManualClock clock{5'000'000'000};
  FakeVideoDevice* device = nullptr;
  std::unique_ptr<V4l2Capture> capture;

  explicit MjpegRig(hal::PixelFormat format) {
    hal::CameraInfo info;
    info.name = "left_eye";
    info.backend = "v4l2";
    info.intrinsics = {kWidth, kHeight, 40.0, 40.0, 23.5, 15.5};
    info.format = format;
    info.rate_hz = 30.0;
    V4l2CameraSettings settings;
    settings.camera = "left_eye";
    settings.device = "/dev/video0";
    settings.pixel_format = "MJPG";
    settings.frame_rate_hz = 30.0;
    settings.buffer_count = 4;
    auto owned = std::make_unique<FakeVideoDevice>(
        DeviceModes{{kFourccMjpeg, {FrameSizeOffer::discrete(kWidth, kHeight, {{1, 30}})}}});
    device = owned.get();
    capture = std::make_unique<V4l2Capture>(info, settings, std::move(owned), clock);
    capture->configure();
    StampMapping mapping;
    mapping.anchor(clock.now_ns(), monotonic_now_ns());
    capture->activate(mapping);
  }
  hal::Status grab(const std::vector<std::uint8_t>& frame, hal::Image& out, int k = 0) {
    EXPECT_TRUE(device->fill(k * kPeriodNs, frame));
    return capture->grab_newest(out);
  }
};

// `image` against OpenCV's decoding of `jpeg` (grey: libjpeg's luma; colour: BGR swapped).
int differing_samples(const hal::Image& image, const std::vector<std::uint8_t>& jpeg) {
  const bool grey = image.format == hal::PixelFormat::kGrey8;
  const cv::Mat peer = cv::imdecode(jpeg, grey ? cv::IMREAD_GRAYSCALE : cv::IMREAD_COLOR);
  EXPECT_EQ(peer.cols, image.width_px);
  EXPECT_EQ(peer.rows, image.height_px);
  int differing = 0;
  for (int y = 0; y < image.height_px; ++y) {
    const std::uint8_t* ours = image.row(y);
    const std::uint8_t* theirs = peer.ptr<std::uint8_t>(y);
    for (int x = 0; x < image.width_px; ++x) {
      if (grey) {
        differing += ours[x] != theirs[x] ? 1 : 0;
      } else {
        for (int c = 0; c < 3; ++c) differing += ours[3 * x + c] != theirs[3 * x + 2 - c] ? 1 : 0;
      }
    }
  }
  return differing;
}

TEST(MjpegCapture, FramesDecodeAsOpenCvDecodesThemGreyAndColour) {
  for (const auto format : {hal::PixelFormat::kGrey8, hal::PixelFormat::kRgb8}) {
    MjpegRig rig(format);
    hal::Image out(kWidth, kHeight, format);
    for (int k = 0; k < 3; ++k) {
      const auto jpeg = jpeg_of(scene(kWidth, kHeight, k + 1));
      ASSERT_EQ(rig.grab(jpeg, out, k), hal::Status::kOk);
      EXPECT_EQ(differing_samples(out, jpeg), 0) << k;
      EXPECT_EQ(out.sequence, static_cast<std::uint64_t>(k + 1));
    }
    EXPECT_EQ(rig.capture->counters().delivered.load(), 3u);
  }
}

TEST(MjpegCapture, FramesWithoutHuffmanTablesUseTheStandardOnes) {
  const auto jpeg = jpeg_of(scene());
  const auto bare = without_huffman_tables(jpeg);
  ASSERT_LT(bare.size(), jpeg.size());
  MjpegRig rig(hal::PixelFormat::kGrey8);
  hal::Image out(kWidth, kHeight, hal::PixelFormat::kGrey8);
  ASSERT_EQ(rig.grab(bare, out), hal::Status::kOk);
  EXPECT_EQ(differing_samples(out, jpeg), 0);
}

TEST(MjpegCapture, DamagedCutShortAndMisSizedFramesAreDroppedAndTheNextDecodes) {
  MjpegRig rig(hal::PixelFormat::kGrey8);
  hal::Image out(kWidth, kHeight, hal::PixelFormat::kGrey8);
  const auto good = jpeg_of(scene());
  auto cut = good;
  cut.resize(cut.size() / 2);
  auto garbage = good;
  std::fill(garbage.begin(), garbage.begin() + 20, std::uint8_t{0x5A});
  const auto other_size = jpeg_of(scene(kWidth - 8, kHeight));
  int k = 0;
  const std::vector<std::uint8_t>* const frames[] = {&cut, &garbage, &other_size, &good};
  for (const std::vector<std::uint8_t>* bad : frames) {
    const hal::Status status = rig.grab(*bad, out, k++);
    if (bad == &good) {
      EXPECT_EQ(status, hal::Status::kOk);
      EXPECT_EQ(differing_samples(out, good), 0);
    } else {
      EXPECT_EQ(status, hal::Status::kRejected) << k;
    }
  }
  EXPECT_EQ(rig.capture->counters().dropped.load(), 3u);
  EXPECT_EQ(rig.capture->counters().delivered.load(), 1u);
}

// libjpeg takes each frame's working memory from malloc (mjpeg_decoder.hpp): the count is the
// same for every frame after the first (which also makes the memory source, kept for the rest):
// nothing grows across frames, and a grab with no new frame allocates nothing.
TEST(MjpegCapture, DecodingAllocatesTheSameSmallNumberOfBlocksEveryFrame) {
  MjpegRig rig(hal::PixelFormat::kRgb8);
  hal::Image out(kWidth, kHeight, hal::PixelFormat::kRgb8);
  std::vector<std::uint64_t> per_frame;
  for (int k = 0; k < 20; ++k) {
    const auto jpeg = jpeg_of(scene(kWidth, kHeight, k));
    ASSERT_TRUE(rig.device->fill(k * kPeriodNs, jpeg));
    const auto before = runtime::thread_allocation_count();
    ASSERT_EQ(rig.capture->grab_newest(out), hal::Status::kOk);
    per_frame.push_back(runtime::thread_allocation_count() - before);
    const auto idle = runtime::thread_allocation_count();
    EXPECT_EQ(rig.capture->grab_newest(out), hal::Status::kNoNewData);
    EXPECT_EQ(runtime::thread_allocation_count(), idle);
  }
  std::printf("MJPEG %dx%d rgb8: %llu allocations per frame (the first %llu)\n", kWidth, kHeight,
              static_cast<unsigned long long>(per_frame[1]),
              static_cast<unsigned long long>(per_frame[0]));
  EXPECT_GT(per_frame[1], 0u);
  EXPECT_LE(per_frame[1], 64u);
  EXPECT_LE(per_frame[0], per_frame[1] + 1);
  for (std::size_t k = 2; k < per_frame.size(); ++k) EXPECT_EQ(per_frame[k], per_frame[1]) << k;
}

TEST(MjpegDecoder, BytesThatAreNoJpegAreRejectedWithoutThrowing) {
  MjpegDecoder decoder;
  hal::Image out(kWidth, kHeight, hal::PixelFormat::kGrey8);
  const std::vector<std::uint8_t> empty;
  const std::vector<std::uint8_t> text = {'n', 'o', 't', ' ', 'a', ' ', 'J', 'P', 'E', 'G'};
  EXPECT_EQ(decoder.decode(empty, out), hal::Status::kRejected);
  EXPECT_EQ(decoder.decode(text, out), hal::Status::kRejected);
  EXPECT_EQ(decoder.decode(jpeg_of(scene()), out), hal::Status::kOk);
}

}  // namespace
}  // namespace cambio::v4l2
