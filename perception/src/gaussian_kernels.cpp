#include "cambio/perception/gaussian_kernels.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace cambio::perception {

double gaussian_kernel_value(int order, Axis axis, double sigma, double x, double y) {
  const double a = -1.0 / (2.0 * sigma * sigma);
  const double lambda = 1.0 / (sigma * std::sqrt(2.0 * std::numbers::pi));
  const double along = axis == Axis::kX ? x : y;
  switch (order) {
    case 0:
      return lambda * std::exp(a * along * along);  // Eq. 3
    case 1:
      return 2.0 * a * lambda * std::exp(a * (x * x + y * y)) * along;  // Eq. 4
    case 2:                                                             // Eq. 5
      return 2.0 * a * lambda * std::exp(a * (x * x + y * y)) * (2.0 * a * along * along + 1.0);
    default:
      throw std::invalid_argument("Gaussian-derivative order must be 0, 1 or 2");
  }
}

int gaussian_half_width(double sigma, double half_width_sigmas) {
  return static_cast<int>(std::ceil(half_width_sigmas * sigma - 1e-9));
}

SeparableKernel gaussian_derivative_kernel(int order, Axis axis, double sigma, int half_width) {
  if (!(sigma > 0.0) || half_width < 0) {
    throw std::invalid_argument("Gaussian kernel needs sigma > 0 and half_width >= 0");
  }
  const double a = -1.0 / (2.0 * sigma * sigma);
  const double lambda = 1.0 / (sigma * std::sqrt(2.0 * std::numbers::pi));
  const std::size_t taps = static_cast<std::size_t>(2 * half_width + 1);
  std::vector<double> along(taps);
  std::vector<double> across(taps);
  for (int t = -half_width; t <= half_width; ++t) {
    const double e = std::exp(a * t * t);
    const std::size_t i = static_cast<std::size_t>(t + half_width);
    across[i] = e;
    switch (order) {
      case 0:
        along[i] = lambda * e;
        break;
      case 1:
        along[i] = 2.0 * a * lambda * e * t;
        break;
      case 2:
        along[i] = 2.0 * a * lambda * e * (2.0 * a * t * t + 1.0);
        break;
      default:
        throw std::invalid_argument("Gaussian-derivative order must be 0, 1 or 2");
    }
  }
  if (order == 0) across.assign(1, 1.0);
  SeparableKernel kernel;
  if (axis == Axis::kX) {
    kernel.row = std::move(along);
    kernel.column = std::move(across);
  } else {
    kernel.row = std::move(across);
    kernel.column = std::move(along);
  }
  return kernel;
}

}  // namespace cambio::perception
