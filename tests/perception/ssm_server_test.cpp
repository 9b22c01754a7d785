// The SSM as a loop: reads fake cameras through the HAL, publishes on latest-value channels and
// never allocates per frame after configure().
#include "cambio/perception/ssm_server.hpp"

#include <gtest/gtest.h>

#include "cambio/runtime/allocation_counter.hpp"
#include "synthetic_images.hpp"

namespace cambio::perception {
namespace {

/// A camera that replays a texture moving 1 px per frame (the right eye sees it shifted).
class TextureCamera final : public hal::Camera {
 public:
  TextureCamera(std::string name, double disparity_px) : disparity_px_(disparity_px) {
    info_.name = std::move(name);
    info_.intrinsics.width_px = 320;
    info_.intrinsics.height_px = 240;
    info_.format = hal::PixelFormat::kGrey8;
    for (int i = 0; i < 4; ++i)
      frames_.push_back(testing::render(texture_, 320, 240, disparity_px_ - i, 0.0));
  }
  const hal::CameraInfo& info() const override { return info_; }
  hal::Status grab(hal::Image& out) override {
    if (out.width_px != 320 || out.height_px != 240) return hal::Status::kRejected;
    const hal::Image& frame = frames_[next_ % frames_.size()];
    std::copy(frame.pixels.begin(), frame.pixels.end(), out.pixels.begin());
    out.sequence = ++next_;
    out.stamp_ns = static_cast<std::int64_t>(next_) * 33'000'000;
    return hal::Status::kOk;
  }

 private:
  testing::Texture texture_{31};
  double disparity_px_;
  hal::CameraInfo info_;
  std::vector<hal::Image> frames_;
  std::size_t next_ = 0;
};

TEST(SsmServer, PublishesDisparityMotionAndMapsWithoutAllocatingPerFrame) {
  TextureCamera left("left", 0.0);
  TextureCamera right("right", 2.5);
  SsmServer server("ssm", left, right, SsmConfig{});
  server.configure();
  server.activate();
  hal::LoopTick tick;
  ASSERT_EQ(server.update(tick), hal::Status::kOk);  // First frame: motion has no history yet.

  const std::uint64_t before = runtime::thread_allocation_count();
  for (int i = 0; i < 20; ++i) {
    tick.cycle = static_cast<std::uint64_t>(i + 1);
    ASSERT_EQ(server.update(tick), hal::Status::kOk);
  }
  const std::uint64_t after = runtime::thread_allocation_count();
  EXPECT_EQ(after - before, 0u) << "allocations in 20 perception cycles";

  SsmSummary summary;
  server.summaries().read(summary);
  EXPECT_EQ(summary.sequence, 21u);
  ASSERT_TRUE(summary.disparity.valid);
  EXPECT_NEAR(summary.disparity.disparity_px, 2.5, 0.1);
  ASSERT_TRUE(summary.motion[0].valid);
  // Frames cycle through 4 positions 1 px apart; 20 updates after the first end on a 1 px step
  // except when wrapping around (-3 px).
  EXPECT_TRUE(std::abs(summary.motion[0].flow_x_px - 1.0f) < 0.1f ||
              std::abs(summary.motion[0].flow_x_px + 3.0f) < 0.15f)
      << summary.motion[0].flow_x_px;
  EXPECT_EQ(summary.fixation[0].x, 160);

  ASSERT_TRUE(server.frames().acquire());
  const SsmFrame& frame = server.frames().front();
  EXPECT_EQ(frame.summary.sequence, 21u);
  EXPECT_EQ(frame.maps[0].levels(), 4);
  EXPECT_NE(frame.maps[0].computed(), 0u);
}

TEST(SsmServer, HonoursRequestedFixationsAndFeatures) {
  TextureCamera left("left", 0.0);
  TextureCamera right("right", 0.0);
  SsmServer server("ssm", left, right, SsmConfig{});
  server.configure();
  SsmRequest request;
  request.fixation_set = true;
  request.fixation = {PixelPoint{100, 90}, PixelPoint{103, 90}};
  request.features.maps = 1;  // intensity only
  request.features.motion = false;
  server.requests().write(request);
  ASSERT_EQ(server.update(hal::LoopTick{}), hal::Status::kOk);
  SsmSummary summary;
  server.summaries().read(summary);
  EXPECT_EQ(summary.fixation[1].x, 103);
  EXPECT_EQ(summary.geometry[0][0].origin_x_px, 100 - 8);
  EXPECT_FALSE(summary.motion[0].valid);
  ASSERT_TRUE(summary.disparity.valid);
  // Same images, right retina 3 px further right: its centre sees a point 3 px left of the
  // left centre, so x_left - x_right (each relative to its fixation) is +3.
  EXPECT_NEAR(summary.disparity.disparity_px, 3.0, 0.1);
}

TEST(SsmServer, RejectsCamerasOfDifferentSizes) {
  class Small final : public hal::Camera {
   public:
    Small() {
      info_.intrinsics.width_px = 10;
      info_.intrinsics.height_px = 10;
    }
    const hal::CameraInfo& info() const override { return info_; }
    hal::Status grab(hal::Image&) override { return hal::Status::kNoNewData; }
    hal::CameraInfo info_;
  } small;
  TextureCamera left("left", 0.0);
  SsmServer server("ssm", left, small, SsmConfig{});
  EXPECT_THROW(server.configure(), std::invalid_argument);
  EXPECT_EQ(server.update(hal::LoopTick{}), hal::Status::kRejected);
}

}  // namespace
}  // namespace cambio::perception
