#include "sim_lens.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cambio/hal/lens_model.hpp"
#include "cambio/hal/luma.hpp"

namespace cambio::sim {

namespace {

// The widest reach of the ideal positions of the image's border pixels beyond the image, left,
// right, top, bottom (the model is monotonic inside the image, so the border bounds the rest).
struct Reach {
  double left = 0.0;
  double right = 0.0;
  double top = 0.0;
  double bottom = 0.0;
};

}  // namespace

std::optional<ImageWindow> SimLens::ideal_window(const hal::CameraIntrinsics& intrinsics,
                                                 const hal::PlumbBobDistortion& distortion,
                                                 std::string* why) {
  const int width = intrinsics.width_px;
  const int height = intrinsics.height_px;
  Reach reach;
  const auto reach_of = [&](double x, double y) {
    double u = 0.0;
    double v = 0.0;
    if (!hal::undistort_px(intrinsics, distortion, x, y, u, v)) {
      if (why != nullptr) {
        *why = "the distortion model folds over inside the image (no ideal pixel maps to (" +
               std::to_string(static_cast<int>(x)) + ", " + std::to_string(static_cast<int>(y)) +
               "))";
      }
      return false;
    }
    reach.left = std::max(reach.left, -u);
    reach.right = std::max(reach.right, u - (width - 1));
    reach.top = std::max(reach.top, -v);
    reach.bottom = std::max(reach.bottom, v - (height - 1));
    return true;
  };
  for (int x = 0; x < width; ++x) {
    if (!reach_of(x, 0) || !reach_of(x, height - 1)) return std::nullopt;
  }
  for (int y = 0; y < height; ++y) {
    if (!reach_of(0, y) || !reach_of(width - 1, y)) return std::nullopt;
  }
  // Centred (the frustum stays symmetric), with a pixel to spare for the bilinear reads.
  const int margin_x = static_cast<int>(std::ceil(std::max(reach.left, reach.right))) + 2;
  const int margin_y = static_cast<int>(std::ceil(std::max(reach.top, reach.bottom))) + 2;
  return ImageWindow{
      width, height, -margin_x, -margin_y, width + 2 * margin_x, height + 2 * margin_y, 1};
}

SimLens::SimLens(const hal::CameraInfo& info) {
  std::string why;
  const std::optional<ImageWindow> window = ideal_window(info.intrinsics, info.distortion, &why);
  if (!window) throw std::invalid_argument("sim camera '" + info.name + "': " + why);
  window_ = *window;
  const int width = info.intrinsics.width_px;
  const int height = info.intrinsics.height_px;
  const std::int32_t row_bytes = 3 * window_.width_px;
  taps_.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double u = 0.0;
      double v = 0.0;
      if (!hal::undistort_px(info.intrinsics, info.distortion, x, y, u, v)) {
        throw std::invalid_argument("sim camera '" + info.name +
                                    "': the distortion model folds over inside the image");
      }
      // Window coordinates; the render's rows run bottom-up.
      const double wx = std::clamp(u - window_.x0_px, 0.0, window_.width_px - 1.001);
      const double wy = std::clamp(v - window_.y0_px, 0.0, window_.height_px - 1.001);
      const int ix = static_cast<int>(wx);
      const int iy = static_cast<int>(wy);
      Tap& tap = taps_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                       static_cast<std::size_t>(x)];
      tap.offset = (window_.height_px - 1 - iy) * row_bytes + 3 * ix;
      tap.fraction_x = static_cast<float>(wx - ix);
      tap.fraction_y = static_cast<float>(wy - iy);
    }
  }
}

std::size_t SimLens::ideal_bytes() const {
  return static_cast<std::size_t>(window_.width_px) * static_cast<std::size_t>(window_.height_px) *
         3;
}

void SimLens::apply(const std::uint8_t* ideal_rgb_bottom_up, hal::Image& out) const noexcept {
  const std::ptrdiff_t row_bytes = 3 * static_cast<std::ptrdiff_t>(window_.width_px);
  const bool rgb = out.format == hal::PixelFormat::kRgb8;
  const int width = out.width_px;
  for (int y = 0; y < out.height_px; ++y) {
    std::uint8_t* target = out.row(y);
    const Tap* tap = taps_.data() + static_cast<std::ptrdiff_t>(y) * width;
    for (int x = 0; x < width; ++x, ++tap) {
      const std::uint8_t* upper = ideal_rgb_bottom_up + tap->offset;
      const std::uint8_t* lower = upper - row_bytes;  // The next row down in the image.
      const float fx = tap->fraction_x;
      const float fy = tap->fraction_y;
      const auto at = [&](int channel) {
        const float top = upper[channel] + fx * (upper[3 + channel] - upper[channel]);
        const float bottom = lower[channel] + fx * (lower[3 + channel] - lower[channel]);
        return top + fy * (bottom - top);
      };
      const auto byte = [](float value) {
        return static_cast<std::uint8_t>(std::clamp(value + 0.5f, 0.0f, 255.0f));
      };
      if (rgb) {
        target[3 * x] = byte(at(0));
        target[3 * x + 1] = byte(at(1));
        target[3 * x + 2] = byte(at(2));
      } else {
        target[x] = hal::luma_bt601(byte(at(0)), byte(at(1)), byte(at(2)));
      }
    }
  }
}

}  // namespace cambio::sim
