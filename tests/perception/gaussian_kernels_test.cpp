// Kernels against the paper's closed forms (Eq. 1-5), written out again here from the paper's
// text so the test does not share code with the implementation.
#include "cambio/perception/gaussian_kernels.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace cambio::perception {
namespace {

// Eq. 1.
double gaussian(double sigma, double x) {
  return std::exp(-x * x / (2 * sigma * sigma)) / (std::sqrt(2 * std::numbers::pi) * sigma);
}

TEST(GaussianKernels, SeparableFactorsReproduceEquations3To5OnTheWholeSquare) {
  for (const double sigma : {1.4, 1.7, 2.7, 4.0}) {
    const int s = gaussian_half_width(sigma, 3.0);
    const double a = -1 / (2 * sigma * sigma);
    const double lambda = 1 / (sigma * std::sqrt(2 * std::numbers::pi));
    for (int order = 0; order <= 2; ++order) {
      for (const Axis axis : {Axis::kX, Axis::kY}) {
        const SeparableKernel k = gaussian_derivative_kernel(order, axis, sigma, s);
        for (int y = -s; y <= s; ++y) {
          for (int x = -s; x <= s; ++x) {
            const double d = axis == Axis::kX ? x : y;
            const double e = std::exp(a * (x * x + y * y));
            double expected = 0;
            if (order == 1) expected = 2 * a * lambda * e * d;
            if (order == 2) expected = 2 * a * lambda * e * (2 * a * d * d + 1);
            if (order == 0) {
              // Eq. 3 depends on d alone: a 1-D mask along d (zero off the d axis).
              const double across = axis == Axis::kX ? y : x;
              expected = across == 0 ? lambda * std::exp(a * d * d) : 0.0;
              const int hx = k.row_half_width();
              const int hy = k.column_half_width();
              const double got = (std::abs(x) <= hx && std::abs(y) <= hy) ? k.value(x, y) : 0.0;
              EXPECT_NEAR(got, expected, 1e-15) << sigma << " " << x << "," << y;
              continue;
            }
            EXPECT_NEAR(k.value(x, y), expected, 1e-15)
                << order << " " << sigma << " " << x << "," << y;
            EXPECT_NEAR(gaussian_kernel_value(order, axis, sigma, x, y), expected, 1e-15);
          }
        }
      }
    }
  }
}

TEST(GaussianKernels, OrdersAreDerivativesOfEquation1) {
  // g^(1) along d = d/dd g_sigma(d) and g^(2) = d^2/dd^2 g_sigma(d), on the d axis.
  const double sigma = 2.7;
  const double h = 1e-4;
  for (double t = -8; t <= 8; t += 0.5) {
    const double first = (gaussian(sigma, t + h) - gaussian(sigma, t - h)) / (2 * h);
    const double second =
        (gaussian(sigma, t + h) - 2 * gaussian(sigma, t) + gaussian(sigma, t - h)) / (h * h);
    EXPECT_NEAR(gaussian_kernel_value(1, Axis::kX, sigma, t, 0), first, 1e-8);
    EXPECT_NEAR(gaussian_kernel_value(2, Axis::kY, sigma, 0, t), second, 1e-5);
    EXPECT_NEAR(gaussian_kernel_value(0, Axis::kX, sigma, t, 3.0), gaussian(sigma, t), 1e-15);
  }
}

TEST(GaussianKernels, HalfWidthIsCeilOfThreeSigmaAndThePapersExampleIsAvailable) {
  EXPECT_EQ(gaussian_half_width(1.4, 3.0), 5);
  EXPECT_EQ(gaussian_half_width(2.7, 3.0), 9);
  EXPECT_EQ(gaussian_half_width(4.0, 3.0), 12);
  EXPECT_EQ(gaussian_half_width(1.0, 3.0), 3);  // exact multiples do not round up
  const SeparableKernel paper = gaussian_derivative_kernel(2, Axis::kX, 1.7, 3);
  EXPECT_EQ(paper.row.size(), 7u);
  EXPECT_EQ(paper.column.size(), 7u);
}

TEST(GaussianKernels, SmoothingMaskSumsToOneAndDerivativeMasksHaveTheirMoments) {
  // A sampled Gaussian with sigma >= 1 sums like its integral over [-L, L], L = s + 1/2, so the
  // moments of the truncated masks are known in closed form (integrating by parts):
  //   sum g0 = P(L), sum t g1 = -P(L) + 2 L g(L), sum t^2 g2 / 2 = P(L) - 2 L g(L) - L^3 g(L) /
  //   sigma^2
  // with P(L) = erf(L / (sigma sqrt 2)) the mass kept.
  for (const double sigma : {1.4, 2.7, 4.0}) {
    const int s = gaussian_half_width(sigma, 3.0);
    double sum0 = 0, moment1 = 0, moment2 = 0;
    for (int t = -s; t <= s; ++t) {
      sum0 += gaussian_kernel_value(0, Axis::kX, sigma, t, 0);
      moment1 += t * gaussian_kernel_value(1, Axis::kX, sigma, t, 0);
      moment2 += t * t * gaussian_kernel_value(2, Axis::kX, sigma, t, 0) / 2;
    }
    const double L = s + 0.5;
    const double mass = std::erf(L / (sigma * std::sqrt(2.0)));
    const double edge = gaussian(sigma, L);
    EXPECT_NEAR(sum0, mass, 1e-4) << sigma;
    EXPECT_NEAR(moment1, -mass + 2 * L * edge, 2e-3) << sigma;
    EXPECT_NEAR(moment2, mass - 2 * L * edge - L * L * L * edge / (sigma * sigma), 5e-3) << sigma;
  }
}

TEST(GaussianKernels, RejectsBadArguments) {
  EXPECT_THROW(gaussian_derivative_kernel(3, Axis::kX, 1.0, 3), std::invalid_argument);
  EXPECT_THROW(gaussian_derivative_kernel(1, Axis::kX, 0.0, 3), std::invalid_argument);
  EXPECT_THROW(gaussian_kernel_value(5, Axis::kX, 1.0, 0, 0), std::invalid_argument);
}

}  // namespace
}  // namespace cambio::perception
