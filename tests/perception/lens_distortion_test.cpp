// The SSM through a real lens: LensDistortion against OpenCV's projectPoints (the same plumb-bob
// model, a peer implementation), and the retina and the SSM's disparity on an image pair warped by
// a known distortion (each distorted pixel is the ideal texture at cv::undistortPoints of it)
// against the same pair unwarped: what the lens-aware retina reads must be the ideal image.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "cambio/perception/lens_distortion.hpp"
#include "cambio/perception/sensory_servo.hpp"
#include "cambio/runtime/allocation_counter.hpp"

namespace cambio::perception {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;

hal::CameraIntrinsics intrinsics() {
  return {kWidth, kHeight, 554.256, 554.256, 319.5, 239.5};
}

/// A wide-angle USB camera's lens (barrel), as calibrate stereo finds on OpenCV's sample views.
hal::PlumbBobDistortion barrel() {
  return {-0.28, 0.07, 0.001, -0.0005, 0.0};
}

/// A band-limited texture defined everywhere: sums of sinusoids with periods of 7-40 px.
class Texture {
 public:
  explicit Texture(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> period(7.0, 40.0);
    std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
    for (auto& wave : waves_) {
      const double p = period(rng);
      const double a = angle(rng);
      wave = {2.0 * M_PI * std::cos(a) / p, 2.0 * M_PI * std::sin(a) / p, angle(rng)};
    }
  }
  double at(double u, double v) const {
    double value = 0.0;
    for (const auto& w : waves_) value += std::sin(w[0] * u + w[1] * v + w[2]);
    return 128.0 + 110.0 * value / static_cast<double>(waves_.size());
  }

 private:
  std::array<std::array<double, 3>, 8> waves_{};
};

/// The image a camera with `lens` makes of `texture` shifted by `shift_px` (x_ideal + shift):
/// each pixel the texture at its ideal position (cv::undistortPoints back to pixels).
hal::Image render(const Texture& texture, double shift_px, const hal::PlumbBobDistortion* lens) {
  hal::Image image;
  image.resize(kWidth, kHeight, hal::PixelFormat::kGrey8);
  std::vector<cv::Point2f> distorted;
  distorted.reserve(static_cast<std::size_t>(kWidth) * kHeight);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) distorted.emplace_back(x, y);
  }
  std::vector<cv::Point2f> ideal = distorted;
  if (lens != nullptr) {
    const hal::CameraIntrinsics k = intrinsics();
    const cv::Matx33d K(k.focal_x_px, 0, k.principal_x_px, 0, k.focal_y_px, k.principal_y_px, 0, 0,
                        1);
    const auto d = lens->opencv_order();
    cv::undistortPoints(
        distorted, ideal, K, std::vector<double>(d.begin(), d.end()), cv::noArray(), K,
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 40, 1e-6));
  }
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const cv::Point2f& p = ideal[static_cast<std::size_t>(y) * kWidth + x];
      image.row(y)[x] = static_cast<std::uint8_t>(
          std::clamp(std::lround(texture.at(p.x + shift_px, p.y)), 0L, 255L));
    }
  }
  return image;
}

TEST(LensDistortion, MapsIdealPixelsAsOpenCvsProjectPoints) {
  const hal::CameraIntrinsics k = intrinsics();
  const LensDistortion lens(k, barrel());
  const cv::Matx33d K(k.focal_x_px, 0, k.principal_x_px, 0, k.focal_y_px, k.principal_y_px, 0, 0,
                      1);
  const auto d = barrel().opencv_order();
  for (double u = 0; u < kWidth; u += 79.0) {
    for (double v = 0; v < kHeight; v += 61.0) {
      const cv::Point3d ray((u - k.principal_x_px) / k.focal_x_px,
                            (v - k.principal_y_px) / k.focal_y_px, 1.0);
      std::vector<cv::Point2d> projected;
      cv::projectPoints(std::vector<cv::Point3d>{ray}, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K,
                        std::vector<double>(d.begin(), d.end()), projected);
      double ud = 0.0;
      double vd = 0.0;
      lens.distort_px(u, v, ud, vd);
      EXPECT_NEAR(ud, projected[0].x, 1e-9) << u << ", " << v;
      EXPECT_NEAR(vd, projected[0].y, 1e-9) << u << ", " << v;
    }
  }
  EXPECT_TRUE(LensDistortion(k, hal::PlumbBobDistortion{}).is_identity());
}

/// Mean absolute difference of two retinas' level k interiors.
double level_difference(const Retina& a, const Retina& b, int k) {
  const RetinaLevelView la = a.level(k);
  const RetinaLevelView lb = b.level(k);
  double sum = 0.0;
  for (int y = 0; y < la.height; ++y) {
    for (int x = 0; x < la.width; ++x) {
      sum += std::abs(la.interior[y * la.stride + x] - lb.interior[y * lb.stride + x]);
    }
  }
  return sum / (la.width * la.height);
}

TEST(LensDistortion, TheRetinaReadsTheIdealImageThroughTheLens) {
  const Texture texture(3);
  const hal::PlumbBobDistortion lens_model = barrel();
  const hal::Image ideal = render(texture, 0.0, nullptr);
  const hal::Image distorted = render(texture, 0.0, &lens_model);
  RetinaConfig config;  // The paper's: 4 levels of 16 x 16.
  Retina truth(config, 6, kWidth, kHeight);
  Retina through(config, 6, kWidth, kHeight);
  Retina naive(config, 6, kWidth, kHeight);
  through.set_lens(LensDistortion(intrinsics(), lens_model));
  // Off-centre, where the lens moves pixels by several px (about 9 px at (480, 360)).
  const PixelPoint fixation{480, 360};
  ASSERT_EQ(truth.build(ideal, fixation), hal::Status::kOk);
  ASSERT_EQ(through.build(distorted, fixation), hal::Status::kOk);
  ASSERT_EQ(naive.build(distorted, fixation), hal::Status::kOk);
  for (int k = 0; k < config.levels; ++k) {
    const double error = level_difference(truth, through, k);
    const double without = level_difference(truth, naive, k);
    std::printf("level %d: mean |ideal - through the lens| %.2f grey levels (read as is: %.2f)\n",
                k, error, without);
    // Rounding to 8 bits twice, and the rectangle standing for a block's slightly bent footprint.
    EXPECT_LT(error, 2.0) << "level " << k;
    EXPECT_GT(without, 5.0 * error) << "level " << k << ": the test cannot tell the lens";
  }
}

/// Every sample of two retinas' level k, apron included: the largest difference.
double largest_difference(const Retina& a, const Retina& b, int k) {
  const RetinaLevelView la = a.level(k);
  const RetinaLevelView lb = b.level(k);
  double largest = 0.0;
  for (int y = -la.apron; y < la.height + la.apron; ++y) {
    for (int x = -la.apron; x < la.width + la.apron; ++x) {
      largest = std::max(largest, static_cast<double>(std::abs(la.interior[y * la.stride + x] -
                                                               lb.interior[y * lb.stride + x])));
    }
  }
  return largest;
}

// A lens that bends nothing measurable still takes the lens path (footprints planned, windows,
// whole-pixel sums, the edges' prefix sums beyond the image): its blocks are then the plain
// retina's blocks, whose means are exact block sums with the edge pixels replicated, so every
// sample, apron and field-covering level included, must agree with the plain path's.
TEST(LensDistortion, ANegligibleLensReadsExactlyWhatThePlainRetinaReads) {
  const Texture texture(11);
  const hal::Image grey = render(texture, 0.0, nullptr);
  hal::Image rgb;
  rgb.resize(kWidth, kHeight, hal::PixelFormat::kRgb8);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::uint8_t v = grey.row(y)[x];
      rgb.row(y)[3 * x] = v;
      rgb.row(y)[3 * x + 1] = static_cast<std::uint8_t>(255 - v);
      rgb.row(y)[3 * x + 2] = static_cast<std::uint8_t>(v / 2);
    }
  }
  hal::PlumbBobDistortion negligible;
  negligible.k1 = 1e-12;
  RetinaConfig config;
  config.coarsest_covers_field = true;
  Retina plain(config, 12, kWidth, kHeight);
  Retina through(config, 12, kWidth, kHeight);
  through.set_lens(LensDistortion(intrinsics(), negligible));
  for (const hal::Image* image : std::array<const hal::Image*, 2>{&grey, &rgb}) {
    for (const PixelPoint fixation :
         {PixelPoint{320, 240}, PixelPoint{5, 470}, PixelPoint{633, 3}, PixelPoint{200, 100}}) {
      ASSERT_EQ(plain.build(*image, fixation), hal::Status::kOk);
      ASSERT_EQ(through.build(*image, fixation), hal::Status::kOk);
      for (int k = 0; k < config.levels; ++k) {
        EXPECT_LT(largest_difference(plain, through, k), 2e-3)
            << (image == &rgb ? "rgb" : "grey") << " level " << k << " at " << fixation.x << ", "
            << fixation.y;
        EXPECT_NEAR(plain.level(k).fraction_inside, through.level(k).fraction_inside, 1e-4);
      }
    }
  }
  // A lens model is for one image size: another is refused, not read with the wrong tables.
  hal::Image smaller;
  smaller.resize(320, 240, hal::PixelFormat::kGrey8);
  EXPECT_EQ(through.build(smaller, PixelPoint{160, 120}), hal::Status::kRejected);
  EXPECT_EQ(through.build_one_level(smaller, 0, PixelPoint{160, 120}), hal::Status::kRejected);
}

TEST(LensDistortion, TheSsmsDisparityThroughTheLensIsTheIdealPairs) {
  const Texture texture(7);
  const hal::PlumbBobDistortion left_lens = barrel();
  hal::PlumbBobDistortion right_lens = barrel();
  right_lens.k1 = -0.25;             // The two eyes' lenses differ a little, as real ones do.
  constexpr double kShift_px = 3.3;  // x_left - x_right of the ideal pair.
  const hal::Image ideal_left = render(texture, 0.0, nullptr);
  const hal::Image ideal_right = render(texture, kShift_px, nullptr);
  const hal::Image left = render(texture, 0.0, &left_lens);
  const hal::Image right = render(texture, kShift_px, &right_lens);
  SsmConfig config;
  config.disparity.scan_range_px = 40.0;
  SensoryServo ideal_ssm(config, kWidth, kHeight);
  SensoryServo lens_ssm(config, kWidth, kHeight);
  SensoryServo naive_ssm(config, kWidth, kHeight);
  lens_ssm.set_lenses(LensDistortion(intrinsics(), left_lens),
                      LensDistortion(intrinsics(), right_lens));
  SsmFrame frame = ideal_ssm.make_frame();
  const FeatureRequest request{.motion = false, .moments = false};
  for (const PixelPoint fixation :
       {PixelPoint{320, 240}, PixelPoint{470, 330}, PixelPoint{150, 120}}) {
    ASSERT_EQ(ideal_ssm.process(ideal_left, ideal_right, fixation, fixation, request, frame),
              hal::Status::kOk);
    const double ideal = frame.summary.disparity.disparity_px;
    ASSERT_TRUE(frame.summary.disparity.valid);
    ASSERT_EQ(lens_ssm.process(left, right, fixation, fixation, request, frame), hal::Status::kOk);
    ASSERT_TRUE(frame.summary.disparity.valid);
    const double through = frame.summary.disparity.disparity_px;
    ASSERT_EQ(naive_ssm.process(left, right, fixation, fixation, request, frame), hal::Status::kOk);
    const double naive = frame.summary.disparity.disparity_px;
    std::printf(
        "fixation (%d, %d): disparity ideal %.3f px, through the lens %.3f px, read as is "
        "%.3f px\n",
        fixation.x, fixation.y, ideal, through, naive);
    EXPECT_NEAR(ideal, kShift_px, 0.1);
    EXPECT_NEAR(through, ideal, 0.1) << fixation.x << ", " << fixation.y;
  }
  // The loop side: reading through the lens allocates nothing, a new fixation included (its
  // footprints are recomputed into the tables set_lenses() sized).
  const std::uint64_t before = runtime::thread_allocation_count();
  for (const PixelPoint fixation :
       {PixelPoint{300, 200}, PixelPoint{300, 200}, PixelPoint{90, 400}}) {
    ASSERT_EQ(lens_ssm.process(left, right, fixation, fixation, FeatureRequest{}, frame),
              hal::Status::kOk);
  }
  EXPECT_EQ(runtime::thread_allocation_count() - before, 0u);
}

}  // namespace
}  // namespace cambio::perception
