// The SSM as a loop: takes stereo pairs from the real camera loop grabbing fake cameras through
// the HAL, publishes on latest-value channels and never allocates per frame after configure().
#include "cambio/perception/ssm_server.hpp"

#include <gtest/gtest.h>

#include "cambio/perception/camera_loop.hpp"

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
    info_.rate_hz = 30.0;
    for (int i = 0; i < 4; ++i)
      frames_.push_back(testing::render(texture_, 320, 240, disparity_px_ - i, 0.0));
  }
  const hal::CameraInfo& info() const override { return info_; }
  hal::Status grab(hal::Image& out) override {
    if (out.width_px != 320 || out.height_px != 240) return hal::Status::kRejected;
    const hal::Image& frame = frames_[next_ % frames_.size()];
    std::copy(frame.pixels.begin(), frame.pixels.end(), out.pixels.begin());
    out.sequence = ++next_;
    out.stamp_ns = static_cast<std::int64_t>(next_) * 33'000'000 + stamp_offset_ns;
    return hal::Status::kOk;
  }

  std::int64_t stamp_offset_ns = 0;  ///< Shifts this camera's stamps (a late exposure).

 private:
  testing::Texture texture_{31};
  double disparity_px_;
  hal::CameraInfo info_;
  std::vector<hal::Image> frames_;
  std::size_t next_ = 0;
};

/// The camera loop and the SSM on one pair of cameras, run cycle by cycle.
struct StereoRig {
  StereoRig(hal::Camera& left, hal::Camera& right)
      : cameras({&left, &right}, StereoPairIndices{0, 1}),
        server("ssm", cameras.stereo_frames(), left.info(), right.info(), SsmConfig{}) {
    cameras.configure();
    server.configure();
    server.activate();
  }
  hal::Status cycle(hal::LoopTick tick = {}) {
    EXPECT_EQ(cameras.update(tick), hal::Status::kOk);
    return server.update(tick);
  }
  CameraLoop cameras;
  SsmServer server;
};

TEST(SsmServer, PublishesDisparityMotionAndMapsWithoutAllocatingPerFrame) {
  TextureCamera left("left", 0.0);
  TextureCamera right("right", 2.5);
  StereoRig rig(left, right);
  SsmServer& server = rig.server;
  SsmRequest request;
  request.features.region = true;  // Every feature, the fixated region too.
  server.requests().write(request);
  hal::LoopTick tick;
  ASSERT_EQ(rig.cycle(tick), hal::Status::kOk);  // First frame: motion has no history yet.

  const std::uint64_t before = runtime::thread_allocation_count();
  for (int i = 0; i < 20; ++i) {
    tick.cycle = static_cast<std::uint64_t>(i + 1);
    ASSERT_EQ(rig.cycle(tick), hal::Status::kOk);
  }
  const std::uint64_t after = runtime::thread_allocation_count();
  EXPECT_EQ(after - before, 0u) << "allocations in 20 camera and perception cycles";

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
  EXPECT_GT(summary.timings.region_us, 0.0);

  ASSERT_TRUE(server.frames().acquire());
  const SsmFrame& frame = server.frames().front();
  EXPECT_EQ(frame.summary.sequence, 21u);
  EXPECT_EQ(frame.maps[0].levels(), 4);
  EXPECT_NE(frame.maps[0].computed(), 0u);
}

TEST(SsmServer, HonoursRequestedFixationsAndFeatures) {
  TextureCamera left("left", 0.0);
  TextureCamera right("right", 0.0);
  StereoRig rig(left, right);
  SsmServer& server = rig.server;
  SsmRequest request;
  request.fixation_set = true;
  request.fixation = {PixelPoint{100, 90}, PixelPoint{103, 90}};
  request.features.maps = 1;  // intensity only
  request.features.motion = false;
  server.requests().write(request);
  ASSERT_EQ(rig.cycle(), hal::Status::kOk);
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
  hal::CameraInfo small;
  small.intrinsics.width_px = 10;
  small.intrinsics.height_px = 10;
  small.rate_hz = 30.0;
  TextureCamera left("left", 0.0);
  hal::TripleBuffer<hal::StereoFrame> pairs;
  SsmServer server("ssm", pairs, left.info(), small, SsmConfig{});
  EXPECT_THROW(server.configure(), std::invalid_argument);
  EXPECT_EQ(server.update(hal::LoopTick{}), hal::Status::kRejected);
}

TEST(SsmServer, RefusesAndCountsPairsWhoseStampsDifferByMoreThanHalfACameraPeriod) {
  TextureCamera left("left", 0.0);
  TextureCamera right("right", 2.5);
  StereoRig rig(left, right);
  EXPECT_EQ(rig.server.max_stamp_skew_ns(), 16'666'666);  // Half of 1/30 s.

  right.stamp_offset_ns = 16'000'000;  // Within half a period: used.
  EXPECT_EQ(rig.cycle(), hal::Status::kOk);
  right.stamp_offset_ns = 17'000'000;  // Beyond: refused, counted, nothing published.
  SsmSummary before;
  ASSERT_TRUE(rig.server.summaries().read(before));
  EXPECT_EQ(rig.cycle(), hal::Status::kRejected);
  EXPECT_EQ(rig.cycle(), hal::Status::kRejected);
  EXPECT_EQ(rig.server.mismatched_pairs(), 2u);
  SsmSummary after;
  ASSERT_TRUE(rig.server.summaries().read(after));
  EXPECT_EQ(after.sequence, before.sequence);
  right.stamp_offset_ns = 0;
  EXPECT_EQ(rig.cycle(), hal::Status::kOk);
  EXPECT_EQ(rig.server.mismatched_pairs(), 2u);
}

/// Delivers a new frame only on the cycles listed (an eye that lags its partner); says its grab()
/// allocates when told to (as the sim's rendered cameras do).
class IntermittentCamera final : public hal::Camera {
 public:
  IntermittentCamera(std::string name, std::vector<bool> delivers, bool grab_allocates = false)
      : delivers_(std::move(delivers)), grab_allocates_(grab_allocates) {
    info_.name = std::move(name);
    info_.intrinsics.width_px = 32;
    info_.intrinsics.height_px = 24;
    info_.format = hal::PixelFormat::kGrey8;
    info_.rate_hz = 30.0;
  }
  const hal::CameraInfo& info() const override { return info_; }
  bool grab_allocates() const override { return grab_allocates_; }
  hal::Status grab(hal::Image& out) override {
    const std::size_t cycle = calls_++;
    if (cycle >= delivers_.size() || !delivers_[cycle]) return hal::Status::kNoNewData;
    out.sequence = ++sequence_;
    out.stamp_ns = static_cast<std::int64_t>(cycle);
    return hal::Status::kOk;
  }

 private:
  hal::CameraInfo info_;
  std::vector<bool> delivers_;
  bool grab_allocates_;
  std::size_t calls_ = 0;
  std::uint64_t sequence_ = 0;
};

TEST(CameraLoop, PublishesAPairOnlyOnceBothEyesDeliveredAndNeverMixesOldAndNew) {
  // The configure() warm-up grab is call 0. Left delivers on cycles 1, 2 and 3; right on 2 and 4.
  IntermittentCamera left("left", {false, true, true, true, false});
  IntermittentCamera right("right", {false, false, true, false, true});
  CameraLoop loop({&left, &right}, StereoPairIndices{0, 1});
  loop.configure();
  auto& pairs = loop.stereo_frames();
  std::vector<std::pair<std::uint64_t, std::uint64_t>> published;
  for (int cycle = 1; cycle <= 4; ++cycle) {
    ASSERT_EQ(loop.update(hal::LoopTick{}), hal::Status::kOk);
    if (pairs.acquire()) {
      published.emplace_back(pairs.front().left.sequence, pairs.front().right.sequence);
    }
  }
  // Cycle 1: left alone waits. Cycle 2: both: pair (2, 1). Cycle 3: left alone. Cycle 4: the
  // right eye's second frame pairs with the newest left one (3, 2).
  const std::vector<std::pair<std::uint64_t, std::uint64_t>> expected{{2, 1}, {3, 2}};
  EXPECT_EQ(published, expected);
  EXPECT_EQ(loop.pairs_published(), 2u);
}

TEST(CameraLoop, AnObserverGetsEveryPublishedPairBesideThePerceptionLoopWithoutAllocating) {
  IntermittentCamera left("left", {false, true, true, true, false});
  IntermittentCamera right("right", {false, false, true, false, true});
  CameraLoop loop({&left, &right}, StereoPairIndices{0, 1});
  auto& observed = loop.observed_stereo_frames();
  loop.configure();
  auto& pairs = loop.stereo_frames();
  std::vector<std::pair<std::uint64_t, std::uint64_t>> seen_by_perception;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> seen_by_observer;
  seen_by_perception.reserve(4);
  seen_by_observer.reserve(4);
  std::size_t observed_pixels = 0;
  const std::uint64_t before = runtime::thread_allocation_count();
  for (int cycle = 1; cycle <= 4; ++cycle) {
    (void)loop.update(hal::LoopTick{});
    if (pairs.acquire()) {
      seen_by_perception.emplace_back(pairs.front().left.sequence, pairs.front().right.sequence);
    }
    if (observed.acquire()) {
      seen_by_observer.emplace_back(observed.front().left.sequence,
                                    observed.front().right.sequence);
      observed_pixels = observed.front().left.pixels.size();
    }
  }
  EXPECT_EQ(runtime::thread_allocation_count() - before, 0u);
  EXPECT_EQ(observed_pixels, 32u * 24u);
  EXPECT_EQ(seen_by_observer, seen_by_perception);
  EXPECT_EQ(seen_by_observer.size(), 2u);
}

TEST(CameraLoop, DeclaresItAllocatesWhenOneOfItsCamerasDoes) {
  IntermittentCamera left("left", {});
  IntermittentCamera right("right", {});
  IntermittentCamera rendered("rendered", {}, /*grab_allocates=*/true);
  EXPECT_FALSE(CameraLoop({&left, &right}, StereoPairIndices{0, 1}).allocates_in_update());
  EXPECT_TRUE(CameraLoop({&left, &rendered}, StereoPairIndices{0, 1}).allocates_in_update());
  EXPECT_TRUE(
      CameraLoop({&left, &right, &rendered}, StereoPairIndices{0, 1}).allocates_in_update());
}

}  // namespace
}  // namespace cambio::perception
