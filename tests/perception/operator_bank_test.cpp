// Feature maps against OpenCV filtering of the same pixels (the retina level with its apron),
// with 2-D masks built here from the paper's closed forms: an independent peer implementation.
#include "cambio/perception/operator_bank.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "cambio/perception/feature_maps.hpp"
#include "synthetic_images.hpp"

namespace cambio::perception {
namespace {

cv::Mat level_with_apron(const RetinaLevelView& level) {
  const int side_w = level.width + 2 * level.apron;
  const int side_h = level.height + 2 * level.apron;
  cv::Mat mat(side_h, side_w, CV_64F);
  for (int y = 0; y < side_h; ++y) {
    for (int x = 0; x < side_w; ++x)
      mat.at<double>(y, x) = level.at(x - level.apron, y - level.apron);
  }
  return mat;
}

// Eq. 3-5 on the square [-s, s]^2 (Eq. 3: the 1-D mask along d), flipped for cv::filter2D
// because Eq. 2 is a convolution and filter2D correlates.
cv::Mat paper_mask(int order, bool along_x, double sigma, int s) {
  const double a = -1 / (2 * sigma * sigma);
  const double lambda = 1 / (sigma * std::sqrt(2 * std::numbers::pi));
  cv::Mat mask = cv::Mat::zeros(2 * s + 1, 2 * s + 1, CV_64F);
  for (int y = -s; y <= s; ++y) {
    for (int x = -s; x <= s; ++x) {
      const double d = along_x ? x : y;
      const double across = along_x ? y : x;
      const double e = std::exp(a * (x * x + y * y));
      double v = 0;
      if (order == 0) v = across == 0 ? lambda * std::exp(a * d * d) : 0.0;
      if (order == 1) v = 2 * a * lambda * e * d;
      if (order == 2) v = 2 * a * lambda * e * (2 * a * d * d + 1);
      mask.at<double>(y + s, x + s) = v;
    }
  }
  cv::Mat flipped;
  cv::flip(mask, flipped, -1);
  return flipped;
}

// Max |ours - reference| must be within 1e-4 of the reference map's largest magnitude.
void expect_map_matches(const float* ours, const cv::Mat& reference, int apron, int width,
                        int height, const std::string& what) {
  double scale = 0;
  double worst = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double ref = reference.at<double>(y + apron, x + apron);
      scale = std::max(scale, std::abs(ref));
      worst = std::max(worst, std::abs(ours[y * width + x] - ref));
    }
  }
  ASSERT_GT(scale, 0.0) << what;
  EXPECT_LE(worst, 1e-4 * scale) << what << ": worst " << worst << " of " << scale;
}

cv::Mat filtered(const cv::Mat& source, const cv::Mat& mask) {
  cv::Mat out;
  cv::filter2D(source, out, CV_64F, mask, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
  return out;
}

class OperatorBankVsOpenCv : public ::testing::TestWithParam<int> {};

TEST_P(OperatorBankVsOpenCv, EveryMapOnEveryLevel) {
  const int side = GetParam();
  OperatorConfig config;
  config.masks.push_back({"prewitt_x", 3, 3, {-1, 0, 1, -1, 0, 1, -1, 0, 1}});  // separable
  config.masks.push_back({"cross", 3, 5, {0, 0, 1, 0, 0, 1, 2, -7, 2, 1, 0, 0, 1, 0, 0}});  // not
  OperatorBank bank(config, side, side);
  ASSERT_EQ(bank.apron_px(), 12);
  RetinaConfig retina_config;
  retina_config.width_px = side;
  retina_config.height_px = side;
  Retina retina(retina_config, bank.apron_px(), 640, 480);
  const hal::Image image = testing::render(testing::Texture(11), 640, 480);
  ASSERT_EQ(retina.build(image, {330, 250}), hal::Status::kOk);
  FeatureMaps maps(retina.levels(), bank.map_count(), side, side);
  for (int k = 0; k < retina.levels(); ++k) {
    bank.apply(retina.level(k), kAllMaps, maps.level(k));
    const cv::Mat source = level_with_apron(retina.level(k));
    const int a = bank.apron_px();
    for (int i = 0; i < bank.map_count(); ++i) {
      const MapSpec& spec = bank.maps()[static_cast<std::size_t>(i)];
      const std::string what = spec.name + " level " + std::to_string(k);
      cv::Mat reference;
      switch (spec.kind) {
        case MapKind::kIntensity:
          reference = source;
          break;
        case MapKind::kGaussian: {
          const int s = static_cast<int>(std::ceil(3 * spec.sigma_px - 1e-9));
          reference =
              filtered(source, paper_mask(spec.order, spec.axis == Axis::kX, spec.sigma_px, s));
          break;
        }
        case MapKind::kLaplacian: {
          const int s = static_cast<int>(std::ceil(3 * spec.sigma_px - 1e-9));
          reference = filtered(source, paper_mask(2, true, spec.sigma_px, s) +
                                           paper_mask(2, false, spec.sigma_px, s));
          break;
        }
        case MapKind::kSobelX:
          cv::Sobel(source, reference, CV_64F, 1, 0, 3);
          break;
        case MapKind::kSobelY:
          cv::Sobel(source, reference, CV_64F, 0, 1, 3);
          break;
        case MapKind::kAverage:
          cv::blur(source, reference, cv::Size(3, 3));
          break;
        case MapKind::kUserMask: {
          const auto& user = spec.name == "prewitt_x" ? config.masks[0] : config.masks[1];
          cv::Mat mask(user.rows, user.cols, CV_64F);
          for (int m = 0; m < user.rows * user.cols; ++m)
            mask.at<double>(m / user.cols, m % user.cols) =
                user.values[static_cast<std::size_t>(m)];
          reference = filtered(source, mask);
          break;
        }
      }
      expect_map_matches(maps.map(k, i), reference, a, side, side, what);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(RetinaSizes, OperatorBankVsOpenCv, ::testing::Values(16, 64));

TEST(OperatorBank, NamesTheMapsAndComputesOnlyWhatIsRequested) {
  OperatorBank bank(OperatorConfig{}, 16, 16);
  // intensity + 3 sigmas x (6 + LoG) + 2 Sobel + average
  EXPECT_EQ(bank.map_count(), 1 + 3 * 7 + 2 + 1);
  EXPECT_EQ(bank.find("g2x@1.4"), 5);
  EXPECT_EQ(bank.find("log@2.7"), 14);
  EXPECT_EQ(bank.find("nope"), -1);
  Retina retina(RetinaConfig{}, bank.apron_px(), 64, 64);
  const hal::Image image = testing::render(testing::Texture(2), 64, 64);
  ASSERT_EQ(retina.build(image, {32, 32}), hal::Status::kOk);
  FeatureMaps maps(4, bank.map_count(), 16, 16);
  for (int i = 0; i < 16 * 16 * bank.map_count(); ++i) maps.level(0)[i] = -12345.0f;
  bank.apply(retina.level(0), MapMask{1} << bank.find("sobel_y"), maps.level(0));
  EXPECT_NE(maps.map(0, bank.find("sobel_y"))[17], -12345.0f);
  EXPECT_EQ(maps.map(0, bank.find("sobel_x"))[17], -12345.0f);
  EXPECT_EQ(maps.map(0, bank.find("g1x@4"))[17], -12345.0f);
}

TEST(OperatorBank, FlatImagesGiveConstantMapsAndRampsGiveTheirSlope) {
  // On a ramp I = 3 x, the normalised first derivative lambda * G_x^(1) is 3 in the interior:
  // an end-to-end check of sign and scale, independent of OpenCV.
  hal::Image ramp(128, 128, hal::PixelFormat::kGrey8);
  for (int y = 0; y < 128; ++y) {
    for (int x = 0; x < 128; ++x) ramp.row(y)[x] = static_cast<std::uint8_t>(std::min(255, 3 * x));
  }
  OperatorBank bank(OperatorConfig{}, 16, 16);
  Retina retina(RetinaConfig{}, bank.apron_px(), 128, 128);
  ASSERT_EQ(retina.build(ramp, {40, 64}), hal::Status::kOk);
  FeatureMaps maps(4, bank.map_count(), 16, 16);
  bank.apply(retina.level(0), kAllMaps, maps.level(0));
  const double sigma = 2.7;
  const double lambda = 1 / (sigma * std::sqrt(2 * std::numbers::pi));
  const float g1x = maps.map(0, bank.find("g1x@2.7"))[8 * 16 + 8];
  EXPECT_NEAR(lambda * g1x, 3.0, 3.0 * 0.01);
  EXPECT_NEAR(maps.map(0, bank.find("sobel_x"))[8 * 16 + 8], 8 * 3.0, 1e-3);
  EXPECT_NEAR(maps.map(0, bank.find("sobel_y"))[8 * 16 + 8], 0.0, 1e-3);
}

TEST(OperatorBank, RejectsBadMasks) {
  OperatorConfig config;
  config.masks.push_back({"even", 2, 2, {1, 1, 1, 1}});
  EXPECT_THROW(OperatorBank(config, 16, 16), std::invalid_argument);
  OperatorConfig clash;
  clash.masks.push_back({"sobel_x", 1, 1, {1}});
  EXPECT_THROW(OperatorBank(clash, 16, 16), std::invalid_argument);
}

}  // namespace
}  // namespace cambio::perception
