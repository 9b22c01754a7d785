// Disparity on stereo pairs with known shifts: right(x) = texture(x + d) puts every scene point
// d px further left in the right image, so disparity_px = x_left - x_right = d.
#include "cambio/perception/disparity_estimator.hpp"

#include <gtest/gtest.h>

#include "cambio/perception/sensory_servo.hpp"
#include "synthetic_images.hpp"

namespace cambio::perception {
namespace {

SsmConfig stereo_config(int side) {
  SsmConfig config;
  config.retina.width_px = side;
  config.retina.height_px = side;
  config.motion.enabled = false;
  config.moments.enabled = false;
  return config;
}

DisparityResult run(const SsmConfig& config, const hal::Image& left, const hal::Image& right,
                    PixelPoint fl, PixelPoint fr) {
  SensoryServo servo(config, left.width_px, left.height_px);
  SsmFrame frame = servo.make_frame();
  FeatureRequest request;
  request.maps = 0;
  EXPECT_EQ(servo.process(left, right, fl, fr, request, frame), hal::Status::kOk);
  return frame.summary.disparity;
}

class KnownShift : public ::testing::TestWithParam<double> {};

TEST_P(KnownShift, PaperRetinaRecoversTheShiftWithinATenthOfAPixel) {
  const double shift = GetParam();
  for (const unsigned seed : {1u, 2u, 3u, 4u}) {
    const testing::Texture texture(seed);
    const hal::Image left = testing::render(texture, 640, 480);
    const hal::Image right = testing::render(texture, 640, 480, shift, 0.0);
    const DisparityResult result = run(stereo_config(16), left, right, {320, 240}, {320, 240});
    ASSERT_TRUE(result.valid) << "seed " << seed;
    EXPECT_EQ(result.level, 0) << "seed " << seed;
    EXPECT_NEAR(result.disparity_px, shift, 0.1) << "seed " << seed;
    EXPECT_GT(result.confidence, 0.5f) << "seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Shifts, KnownShift,
                         ::testing::Values(0.0, 1.0, -2.0, 3.0, 0.25, -0.5, 0.7, 2.4, -1.3));

TEST(Disparity, CoarseToFineFindsLargeShifts) {
  // A 64-px retina with a 17-px window (half 8) overlaps shifts up to 64/2 - 8 = 24 px in the
  // fovea; beyond that the SSM moves the right window onto the coarser estimate, so every shift
  // the coarsest level finds is refined down to the fovea, within 0.1 px.
  SsmConfig config = stereo_config(64);
  config.disparity.window_half_px = 8;
  config.disparity.search_range_px = 64;
  for (const double shift : {9.0, -14.0, 21.6, 30.0, -41.3}) {
    const testing::Texture texture(21);
    const hal::Image left = testing::render(texture, 640, 480);
    const hal::Image right = testing::render(texture, 640, 480, shift, 0.0);
    const DisparityResult result = run(config, left, right, {320, 240}, {320, 240});
    ASSERT_TRUE(result.valid) << shift;
    EXPECT_EQ(result.level, 0) << shift;
    EXPECT_NEAR(result.disparity_px, shift, 0.1) << shift;
    EXPECT_EQ(result.per_level[0].moved_windows > 0, std::abs(shift) > 24 - 2) << shift;
  }
}

TEST(Disparity, PaperRetinaRefinesBeyondTheFoveasOverlapInTheFovea) {
  // 16-px foveas with a 9-px window overlap only -3 .. +4 px; at 26 px the finer levels score
  // moved right windows and the fovea still gives the estimate to a tenth of a pixel.
  const testing::Texture texture(5);
  const hal::Image left = testing::render(texture, 640, 480);
  const hal::Image right = testing::render(texture, 640, 480, 26.0, 0.0);
  const DisparityResult result = run(stereo_config(16), left, right, {320, 240}, {320, 240});
  ASSERT_TRUE(result.valid);
  EXPECT_EQ(result.level, 0);
  EXPECT_NEAR(result.disparity_px, 26.0, 0.1);
  EXPECT_GT(result.per_level[0].moved_windows, 0);
  EXPECT_GT(result.confidence, 0.5f);
}

TEST(Disparity, WithoutAShiftedSourceTheFinestLevelThatStillOverlapsReports) {
  // The estimator alone (no ShiftedLevelSource) cannot look past the overlap: at 26 px the
  // estimate comes from a coarser level, to within that level's accuracy, and the fovea says it
  // was not searched.
  const SsmConfig config = stereo_config(16);
  const testing::Texture texture(5);
  const hal::Image left = testing::render(texture, 640, 480);
  const hal::Image right = testing::render(texture, 640, 480, 26.0, 0.0);
  const OperatorBank bank(config.operators, 16, 16);
  const DisparityEstimator estimator(config.disparity, bank, 16, 16);
  Retina left_retina(config.retina, bank.apron_px(), 640, 480);
  Retina right_retina(config.retina, bank.apron_px(), 640, 480);
  ASSERT_EQ(left_retina.build(left, {320, 240}), hal::Status::kOk);
  ASSERT_EQ(right_retina.build(right, {320, 240}), hal::Status::kOk);
  FeatureMaps left_maps(config.retina.levels, bank.map_count(), 16, 16);
  FeatureMaps right_maps(config.retina.levels, bank.map_count(), 16, 16);
  for (int k = 0; k < config.retina.levels; ++k) {
    bank.apply(left_retina.level(k), estimator.required_maps(), left_maps.level(k));
    bank.apply(right_retina.level(k), estimator.required_maps(), right_maps.level(k));
  }
  DisparityResult result;
  estimator.estimate(left_maps, right_maps, left_retina, right_retina, result);
  ASSERT_TRUE(result.valid);
  EXPECT_GT(result.level, 0);
  EXPECT_NEAR(result.disparity_px, 26.0, 0.25 * (1 << result.level));
  EXPECT_FALSE(result.per_level[0].searched);
}

TEST(Disparity, BeyondTheSearchableRangeIsNotAConfidentWrongNumber) {
  // The paper retina's coarsest level reaches 4 x 8 = 32 px; 60 px lies outside.
  const testing::Texture texture(6);
  const hal::Image left = testing::render(texture, 640, 480);
  const hal::Image right = testing::render(texture, 640, 480, 60.0, 0.0);
  const DisparityResult result = run(stereo_config(16), left, right, {320, 240}, {320, 240});
  EXPECT_TRUE(!result.valid || result.confidence <= 0.5f ||
              std::abs(result.disparity_px - 60.0) < 2.0)
      << result.disparity_px << " confidence " << result.confidence;
}

TEST(Disparity, IsRelativeToEachRetinasFixation) {
  // Fixating the right eye 6 px to the left of the left eye's fixation on a pair with 6 px of
  // image disparity puts both retinas on the same scene point: zero vergence error.
  const testing::Texture texture(8);
  const hal::Image left = testing::render(texture, 640, 480);
  const hal::Image right = testing::render(texture, 640, 480, 6.0, 0.0);
  const DisparityResult result = run(stereo_config(16), left, right, {300, 200}, {294, 200});
  ASSERT_TRUE(result.valid);
  EXPECT_NEAR(result.disparity_px, 0.0, 0.1);
}

TEST(Disparity, UntexturedPairsAreInvalidOrLowConfidence) {
  const SsmConfig config = stereo_config(16);
  {
    const hal::Image left = testing::flat(320, 240, 120, 0.0, 1);
    const DisparityResult result = run(config, left, left, {160, 120}, {160, 120});
    EXPECT_FALSE(result.valid);
    EXPECT_EQ(result.confidence, 0.0f);
  }
  {
    // Independent sensor noise only: nothing to match.
    const hal::Image left = testing::flat(320, 240, 120, 1.0, 1);
    const hal::Image right = testing::flat(320, 240, 120, 1.0, 2);
    const DisparityResult result = run(config, left, right, {160, 120}, {160, 120});
    EXPECT_TRUE(!result.valid || result.confidence < 0.3f) << result.confidence;
  }
}

TEST(Disparity, UnknownFeatureNamesAreRejected) {
  SsmConfig config = stereo_config(16);
  config.disparity.features = {"g2x@1.5"};
  EXPECT_THROW(SensoryServo(config, 64, 64), std::invalid_argument);
}

}  // namespace
}  // namespace cambio::perception
