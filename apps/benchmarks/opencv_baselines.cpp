#include "opencv_baselines.hpp"

#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "bench_timing.hpp"
#include "cambio/perception/gaussian_kernels.hpp"

namespace cambio::app {

namespace {

/// The SSM's operator set on a whole image with OpenCV.
class FullImageFilter {
 public:
  explicit FullImageFilter(const perception::OperatorConfig& ops) {
    for (const double sigma : ops.sigmas_px) {
      const int s = perception::gaussian_half_width(sigma, ops.half_width_sigmas);
      Family family;
      family.order0 =
          as_mat(perception::gaussian_derivative_kernel(0, perception::Axis::kX, sigma, s).row);
      const auto first = perception::gaussian_derivative_kernel(1, perception::Axis::kX, sigma, s);
      family.order1 = as_mat(first.row);
      family.across = as_mat(first.column);
      family.order2 =
          as_mat(perception::gaussian_derivative_kernel(2, perception::Axis::kX, sigma, s).row);
      families_.push_back(family);
    }
  }
  void run(const hal::Image& image) {
    const cv::Mat grey(image.height_px, image.width_px, CV_8U,
                       const_cast<std::uint8_t*>(image.pixels.data()));
    grey.convertTo(source_, CV_32F);
    const cv::Mat one = cv::Mat::ones(1, 1, CV_32F);
    for (const auto& f : families_) {
      // filter2D-family functions correlate; the masks are flipped to convolve (Eq. 2).
      cv::sepFilter2D(source_, out_[0], CV_32F, flip(f.order0), one);
      cv::sepFilter2D(source_, out_[1], CV_32F, one, flip(f.order0));
      cv::sepFilter2D(source_, out_[2], CV_32F, flip(f.order1), f.across);
      cv::sepFilter2D(source_, out_[3], CV_32F, f.across, flip(f.order1));
      cv::sepFilter2D(source_, out_[4], CV_32F, f.order2, f.across);
      cv::sepFilter2D(source_, out_[5], CV_32F, f.across, f.order2);
      cv::add(out_[4], out_[5], out_[6]);
    }
    cv::Sobel(source_, out_[7], CV_32F, 1, 0, 3);
    cv::Sobel(source_, out_[8], CV_32F, 0, 1, 3);
    cv::blur(source_, out_[9], cv::Size(3, 3));
  }

 private:
  struct Family {
    cv::Mat order0, order1, order2, across;
  };
  static cv::Mat as_mat(const std::vector<double>& taps) {
    cv::Mat mat(static_cast<int>(taps.size()), 1, CV_32F);
    for (std::size_t i = 0; i < taps.size(); ++i)
      mat.at<float>(static_cast<int>(i)) = static_cast<float>(taps[i]);
    return mat;
  }
  static cv::Mat flip(const cv::Mat& taps) {
    cv::Mat flipped;
    cv::flip(taps, flipped, 0);
    return flipped;
  }
  std::vector<Family> families_;
  cv::Mat source_;
  std::array<cv::Mat, 10> out_;
};

/// A grey8 image as a cv::Mat over its pixels (no copy; OpenCV only reads it here).
cv::Mat grey_mat(const hal::Image& image) {
  return cv::Mat(image.height_px, image.width_px, CV_8U,
                 const_cast<std::uint8_t*>(image.pixels.data()));
}

}  // namespace

double time_full_image_filter(const perception::OperatorConfig& ops, const hal::Image& left,
                              const hal::Image& right, int repeats) {
  FullImageFilter full(ops);
  return median_us(repeats, [&] {
    full.run(left);
    full.run(right);
  });
}

double time_stereo_bm(const hal::Image& left, const hal::Image& right, int repeats) {
  const cv::Mat left_mat = grey_mat(left);
  const cv::Mat right_mat = grey_mat(right);
  cv::Ptr<cv::StereoBM> matcher = cv::StereoBM::create(64, 15);
  cv::Mat disparity;
  return median_us(repeats, [&] { matcher->compute(left_mat, right_mat, disparity); });
}

}  // namespace cambio::app
