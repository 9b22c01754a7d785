#include "cambio/control/vergence_controller.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cambio::control {
namespace {

constexpr double kFocalPx = 554.256;

VergenceParams params(hal::Eye eye, double gain = 1.0) {
  VergenceParams p;
  p.verging_eye = eye;
  p.focal_px = kFocalPx;
  p.gain = gain;
  p.min_confidence = 0.3;
  p.max_step_rad = 0.5;
  return p;
}

// A pinhole eye turned by `pan` sees a point at bearing `bearing` (both about the vertical,
// positive to the left) at x = cx - f * tan(bearing - pan). The disparity x_left - x_right with
// the left eye on the point is then f * tan(bearing_right - pan_right).
double disparity_for(double bearing_right_rad, double pan_right_rad) {
  return kFocalPx * std::tan(bearing_right_rad - pan_right_rad);
}

TEST(VergenceController, FullGainCorrectsTheWholeAngleInOneStep) {
  const VergenceController controller(params(hal::Eye::kRight));
  const double bearing = 0.2054;  // Where the right eye must look (rad).
  const double pan = 0.0831;      // Parallel to the left eye.
  const double target =
      controller.next_target_rad(pan, pan, {true, disparity_for(bearing, pan), 0.9});
  EXPECT_NEAR(target, bearing, 1e-12);
}

TEST(VergenceController, LeftEyeVergingTurnsTheOtherWay) {
  const VergenceController controller(params(hal::Eye::kLeft));
  // With the right eye on the point, a positive disparity puts it right of the left image's
  // centre: the left eye must turn right (negative pan).
  const double target = controller.next_target_rad(0.1, 0.2, {true, 20.0, 0.9});
  EXPECT_NEAR(target, 0.1 - std::atan(20.0 / kFocalPx), 1e-12);
}

TEST(VergenceController, PartialGainConvergesGeometrically) {
  const VergenceController controller(params(hal::Eye::kRight, 0.5));
  const double bearing = 0.2054;
  double pan = 0.0831;
  for (int i = 0; i < 20; ++i) {
    pan = controller.next_target_rad(pan, 0.0831, {true, disparity_for(bearing, pan), 0.9});
  }
  EXPECT_NEAR(pan, bearing, 1e-6);
}

TEST(VergenceController, IgnoresInvalidAndLowConfidenceMeasurements) {
  const VergenceController controller(params(hal::Eye::kRight));
  EXPECT_EQ(controller.next_target_rad(0.1, 0.0, {false, 30.0, 0.9}), 0.1);
  EXPECT_EQ(controller.next_target_rad(0.1, 0.0, {true, 30.0, 0.29}), 0.1);
  EXPECT_EQ(controller.next_target_rad(0.1, 0.0, {true, std::nan(""), 0.9}), 0.1);
}

TEST(VergenceController, NeverDiverges) {
  const VergenceController right(params(hal::Eye::kRight));
  // A large negative disparity would turn the right eye past parallel: it stops at parallel.
  EXPECT_DOUBLE_EQ(right.next_target_rad(0.05, 0.04, {true, -200.0, 0.9}), 0.04);
  const VergenceController left(params(hal::Eye::kLeft));
  EXPECT_DOUBLE_EQ(left.next_target_rad(-0.05, -0.04, {true, -200.0, 0.9}), -0.04);
}

TEST(VergenceController, LimitsTheStepPerMeasurement) {
  auto p = params(hal::Eye::kRight);
  p.max_step_rad = 0.01;
  const VergenceController controller(p);
  EXPECT_NEAR(controller.next_target_rad(0.0, 0.0, {true, 100.0, 0.9}), 0.01, 1e-15);
}

TEST(VergenceController, RefusesBadParameters) {
  auto p = params(hal::Eye::kRight);
  p.gain = 1.5;
  EXPECT_THROW(VergenceController{p}, std::invalid_argument);
  p = params(hal::Eye::kRight);
  p.focal_px = 0;
  EXPECT_THROW(VergenceController{p}, std::invalid_argument);
  // The gains have no defaults of their own (the experiment config holds them): unset is refused.
  p = VergenceParams{};
  p.focal_px = kFocalPx;
  EXPECT_THROW(VergenceController{p}, std::invalid_argument);
}

}  // namespace
}  // namespace cambio::control
