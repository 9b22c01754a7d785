#pragma once

#include <vector>

namespace cambio::perception {

/// The direction d of a Gaussian-derivative operator (paper Eq. 2).
enum class Axis { kX, kY };

/// Closed form of the paper's kernels, Eq. 3-5, at integer or real (x, y), with
/// a = -1/(2 sigma^2) and lambda = 1/(sigma sqrt(2 pi)):
///   order 0: g_x = lambda e^(a x^2)                     (a function of x alone: a 1-D mask)
///   order 1: g_x = 2 a lambda e^(a (x^2 + y^2)) x
///   order 2: g_x = 2 a lambda e^(a (x^2 + y^2)) (2 a x^2 + 1)
/// and the same with x and y exchanged for Axis::kY. Orders 1 and 2 are the first and second
/// derivatives of Eq. 1 along d times an unnormalised Gaussian e^(a t^2) across d.
double gaussian_kernel_value(int order, Axis axis, double sigma, double x, double y);

/// The default half-width: s = ceil(half_width_sigmas * sigma). With 3 sigma the mask keeps
/// 99.7% of the Gaussian's mass and its edge taps are 1.1% of the peak; the paper's example
/// (sigma 1.7, s = 3, i.e. 1.76 sigma) cuts at 21% of the peak, which leaves a large DC
/// response in the derivative masks.
int gaussian_half_width(double sigma, double half_width_sigmas);

/// A mask written as the outer product of a row (along x) and a column (along y) factor, each
/// indexed from -half_width to +half_width: value(x, y) = row[x + hx] * column[y + hy]. The
/// masks are convolution kernels (Eq. 2): out(p) = sum_t k(t) in(p - t).
struct SeparableKernel {
  std::vector<double> row;
  std::vector<double> column;
  int row_half_width() const { return static_cast<int>(row.size() / 2); }
  int column_half_width() const { return static_cast<int>(column.size() / 2); }
  double value(int x, int y) const {
    return row[static_cast<std::size_t>(x + row_half_width())] *
           column[static_cast<std::size_t>(y + column_half_width())];
  }
};

/// Eq. 3-5 as separable factors on [-s, s]^2 (order 0: the 1-D mask, column = {1}).
SeparableKernel gaussian_derivative_kernel(int order, Axis axis, double sigma, int half_width);

}  // namespace cambio::perception
