#include "cambio/perception/operator_bank.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace cambio::perception {

namespace {

std::string sigma_label(double sigma) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", sigma);
  return text;
}

int half_width_for(const OperatorConfig& config, double sigma) {
  return config.half_width_px > 0 ? config.half_width_px
                                  : gaussian_half_width(sigma, config.half_width_sigmas);
}

// A correlation mask M(r, c) = column[r] * row[c] becomes the convolution factors reversed.
// Returns false unless every entry matches the rank-1 product to 1e-6 of the largest entry.
bool split_rank_one(const UserMask& mask, std::vector<double>& row, std::vector<double>& column) {
  std::size_t pivot = 0;
  for (std::size_t i = 1; i < mask.values.size(); ++i) {
    if (std::abs(mask.values[i]) > std::abs(mask.values[pivot])) pivot = i;
  }
  const double peak = mask.values[pivot];
  if (peak == 0.0) return false;
  const int pr = static_cast<int>(pivot) / mask.cols;
  const int pc = static_cast<int>(pivot) % mask.cols;
  row.assign(static_cast<std::size_t>(mask.cols), 0.0);
  column.assign(static_cast<std::size_t>(mask.rows), 0.0);
  for (int c = 0; c < mask.cols; ++c) {
    row[static_cast<std::size_t>(mask.cols - 1 - c)] =
        mask.values[static_cast<std::size_t>(pr * mask.cols + c)] / peak;
  }
  for (int r = 0; r < mask.rows; ++r) {
    column[static_cast<std::size_t>(mask.rows - 1 - r)] =
        mask.values[static_cast<std::size_t>(r * mask.cols + pc)];
  }
  for (int r = 0; r < mask.rows; ++r) {
    for (int c = 0; c < mask.cols; ++c) {
      const double product = column[static_cast<std::size_t>(mask.rows - 1 - r)] *
                             row[static_cast<std::size_t>(mask.cols - 1 - c)];
      if (std::abs(product - mask.values[static_cast<std::size_t>(r * mask.cols + c)]) >
          1e-6 * std::abs(peak)) {
        return false;
      }
    }
  }
  return true;
}

}  // namespace

std::vector<MapSpec> feature_map_specs(const OperatorConfig& config) {
  std::vector<MapSpec> specs;
  specs.push_back({"intensity", MapKind::kIntensity, 0, Axis::kX, 0.0});
  for (const double sigma : config.sigmas_px) {
    const std::string label = sigma_label(sigma);
    for (int order = 0; order <= 2; ++order) {
      for (const Axis axis : {Axis::kX, Axis::kY}) {
        specs.push_back({"g" + std::to_string(order) + (axis == Axis::kX ? "x@" : "y@") + label,
                         MapKind::kGaussian, order, axis, sigma});
      }
    }
    if (config.laplacian_of_gaussian) {
      specs.push_back({"log@" + label, MapKind::kLaplacian, 2, Axis::kX, sigma});
    }
  }
  if (config.sobel) {
    specs.push_back({"sobel_x", MapKind::kSobelX, 1, Axis::kX, 0.0});
    specs.push_back({"sobel_y", MapKind::kSobelY, 1, Axis::kY, 0.0});
  }
  if (config.average_radius_px > 0)
    specs.push_back({"average", MapKind::kAverage, 0, Axis::kX, 0.0});
  for (const auto& mask : config.masks)
    specs.push_back({mask.name, MapKind::kUserMask, 0, Axis::kX, 0.0});
  return specs;
}

OperatorBank::OperatorBank(const OperatorConfig& config, int width, int height)
    : width_(width), height_(height), specs_(feature_map_specs(config)) {
  if (static_cast<int>(specs_.size()) > kMaxMaps) {
    throw std::invalid_argument("the operator set produces more than 64 maps");
  }
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (specs_[i].name == specs_[j].name) {
        throw std::invalid_argument("two feature maps are named '" + specs_[i].name + "'");
      }
    }
  }
  for (const double sigma : config.sigmas_px) {
    if (!(sigma > 0.0)) throw std::invalid_argument("Gaussian sigma must be positive");
    GaussianFamily family;
    family.sigma_px = sigma;
    family.half_width = half_width_for(config, sigma);
    const int s = family.half_width;
    family.order0 = Taps::from(gaussian_derivative_kernel(0, Axis::kX, sigma, s).row);
    const SeparableKernel first = gaussian_derivative_kernel(1, Axis::kX, sigma, s);
    family.order1 = Taps::from(first.row);
    family.across = Taps::from(first.column);
    family.order2 = Taps::from(gaussian_derivative_kernel(2, Axis::kX, sigma, s).row);
    family.order0_over_across = family.order0.centre()[0] / family.across.centre()[0];
    family.first_map = find("g0x@" + sigma_label(sigma));
    family.laplacian_map = find("log@" + sigma_label(sigma));
    apron_ = std::max(apron_, s);
    gaussians_.push_back(std::move(family));
  }
  if (config.sobel) {
    sobel_map_ = find("sobel_x");
    sobel_derivative_ = Taps::from({1.0, 0.0, -1.0});
    sobel_smooth_ = Taps::from({1.0, 2.0, 1.0});
    apron_ = std::max(apron_, 1);
  }
  if (config.average_radius_px > 0) {
    average_map_ = find("average");
    const int r = config.average_radius_px;
    box_ = Taps::from(std::vector<double>(static_cast<std::size_t>(2 * r + 1), 1.0 / (2 * r + 1)));
    apron_ = std::max(apron_, r);
  }
  for (const auto& user : config.masks) {
    if (user.rows < 1 || user.cols < 1 || user.rows % 2 == 0 || user.cols % 2 == 0 ||
        user.values.size() != static_cast<std::size_t>(user.rows * user.cols)) {
      throw std::invalid_argument("mask '" + user.name +
                                  "' needs odd rows and cols and rows * cols values");
    }
    Mask mask;
    mask.map = find(user.name);
    mask.rows = user.rows;
    mask.cols = user.cols;
    mask.values.assign(user.values.begin(), user.values.end());
    std::vector<double> row;
    std::vector<double> column;
    mask.separable = split_rank_one(user, row, column);
    if (mask.separable) {
      mask.row = Taps::from(row);
      mask.column = Taps::from(column);
    }
    apron_ = std::max({apron_, user.rows / 2, user.cols / 2});
    masks_.push_back(std::move(mask));
  }
  scratch_.assign(
      3 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height + 2 * apron_), 0.0f);
}

int OperatorBank::find(std::string_view name) const {
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    if (specs_[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

void OperatorBank::apply_separable(const RetinaLevelView& level, const Taps& row,
                                   const Taps& column, float* out) const noexcept {
  const int s = column.half_width;
  float* rows = scratch_.data();
  convolve_rows(level.interior - s * level.stride, level.stride, rows, width_, width_,
                height_ + 2 * s, row);
  convolve_columns(rows + s * width_, width_, out, width_, width_, height_, column);
}

void OperatorBank::apply(const RetinaLevelView& level, MapMask request, float* out) const noexcept {
  const auto wanted = [request](int map) { return map >= 0 && ((request >> map) & 1u) != 0; };
  if (wanted(0)) {
    for (int y = 0; y < height_; ++y) {
      std::copy_n(level.interior + y * level.stride, width_, map_out(out, 0) + y * width_);
    }
  }
  const std::ptrdiff_t plane = static_cast<std::ptrdiff_t>(width_) * (height_ + 2 * apron_);
  for (const auto& family : gaussians_) {
    const int first = family.first_map;
    bool any = wanted(family.laplacian_map);
    for (int i = 0; i < 6; ++i) any = any || wanted(first + i);
    if (!any) continue;
    const int s = family.half_width;
    const float* top = level.interior - s * level.stride;
    const int rows = height_ + 2 * s;
    // Row passes over the interior columns of every row the column passes will read.
    float* along1 = scratch_.data();
    float* along2 = along1 + plane;
    float* across = along2 + plane;
    // One pass for the three (Eq. 3-5 share the rows and the folded tap pairs).
    if (!convolve_rows_family(top, level.stride, width_, width_, rows, family.order1, along1,
                              family.order2, along2, family.across, across)) {
      convolve_rows(top, level.stride, along1, width_, width_, rows, family.order1);
      convolve_rows(top, level.stride, along2, width_, width_, rows, family.order2);
      convolve_rows(top, level.stride, across, width_, width_, rows, family.across);
    }
    const std::ptrdiff_t centre = static_cast<std::ptrdiff_t>(s) * width_;
    // Eq. 3: 1-D masks along d. Along x, the order-0 mask is lambda e^(a t^2), the across pass
    // scaled by lambda: its interior rows give g0x without another pass.
    {
      const float* source = across + centre;
      float* g0x = map_out(out, first + 0);
      const float factor = family.order0_over_across;
      for (int i = 0; i < width_ * height_; ++i) g0x[i] = factor * source[i];
    }
    convolve_columns(level.interior, level.stride, map_out(out, first + 1), width_, width_, height_,
                     family.order0);
    // Eq. 4-5: derivative along d times e^(a t^2) across d.
    convolve_columns(along1 + centre, width_, map_out(out, first + 2), width_, width_, height_,
                     family.across);
    convolve_columns(along2 + centre, width_, map_out(out, first + 4), width_, width_, height_,
                     family.across);
    // g1y and g2y read the same across plane: one pass for both.
    if (!convolve_columns_pair(across + centre, width_, width_, width_, height_, family.order1,
                               map_out(out, first + 3), family.order2, map_out(out, first + 5))) {
      convolve_columns(across + centre, width_, map_out(out, first + 3), width_, width_, height_,
                       family.order1);
      convolve_columns(across + centre, width_, map_out(out, first + 5), width_, width_, height_,
                       family.order2);
    }
    if (family.laplacian_map >= 0 && wanted(family.laplacian_map)) {
      const float* xx = map_out(out, first + 4);
      const float* yy = map_out(out, first + 5);
      float* laplacian = map_out(out, family.laplacian_map);
      for (int i = 0; i < width_ * height_; ++i) laplacian[i] = xx[i] + yy[i];
    }
  }
  if (sobel_map_ >= 0 && wanted(sobel_map_)) {
    apply_separable(level, sobel_derivative_, sobel_smooth_, map_out(out, sobel_map_));
  }
  if (sobel_map_ >= 0 && wanted(sobel_map_ + 1)) {
    apply_separable(level, sobel_smooth_, sobel_derivative_, map_out(out, sobel_map_ + 1));
  }
  if (wanted(average_map_)) apply_separable(level, box_, box_, map_out(out, average_map_));
  for (const auto& mask : masks_) {
    if (!wanted(mask.map)) continue;
    if (mask.separable) {
      apply_separable(level, mask.row, mask.column, map_out(out, mask.map));
    } else {
      correlate_2d(level.interior, level.stride, map_out(out, mask.map), width_, width_, height_,
                   mask.values.data(), mask.rows, mask.cols);
    }
  }
}

}  // namespace cambio::perception
