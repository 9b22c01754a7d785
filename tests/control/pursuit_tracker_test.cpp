// The pursuit tracker against a target moving at a known image speed, fed motion estimates whose
// frame-to-frame flows are biased (as Lucas-Kanade's are on large or one-dimensional motion) and
// whose displacements since the key frame are not.
#include "cambio/control/pursuit_tracker.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace cambio::control {
namespace {

constexpr double kFocalPx = 500.0;
constexpr double kSpeedPxPerFrame = 2.0;
constexpr double kFlowBias = 0.9;  ///< Frame flows read 10% short.
constexpr std::int64_t kFramePeriodNs = 33'333'333;

hal::CameraIntrinsics intrinsics() {
  hal::CameraIntrinsics camera;
  camera.width_px = 640;
  camera.height_px = 480;
  camera.focal_x_px = kFocalPx;
  camera.focal_y_px = kFocalPx;
  return camera;
}

/// Frame n (1-based) of a still camera: the target, at the image centre in frame 1, is
/// kSpeedPxPerFrame * (n - 1) px to the right. Keys are frames 1, 1 + every, 1 + 2 every, ...
perception::MotionResult frame_motion(int n, int every, bool with_key) {
  perception::MotionResult motion;
  motion.frame = static_cast<std::uint64_t>(n);
  if (n == 1) return motion;
  motion.valid = true;
  motion.flow_x_px = static_cast<float>(kFlowBias * kSpeedPxPerFrame);
  const int key = 1 + ((n - 2) / every) * every;
  motion.key_valid = with_key;
  motion.key_frame = static_cast<std::uint64_t>(key);
  motion.key_flow_x_px = static_cast<float>(kSpeedPxPerFrame * (n - key));
  return motion;
}

/// The tracker's image x (px) of the target after `frames` frames.
double tracked_x_px(int frames, int every, bool with_key) {
  PursuitTracker tracker(intrinsics(), 0.1);
  const Eigen::Matrix3d R_WC = Eigen::Matrix3d::Identity();
  tracker.start(Eigen::Vector3d::UnitZ(), R_WC, 0);
  for (int n = 1; n <= frames; ++n) {
    tracker.update(frame_motion(n, every, with_key), R_WC, n * kFramePeriodNs);
  }
  const Eigen::Vector3d d = tracker.direction_W(frames * kFramePeriodNs);
  return kFocalPx * d.x() / d.z();
}

TEST(PursuitTracker, PlacesTheTargetByTheDisplacementSinceTheKeyWithoutSummingFlowErrors) {
  constexpr int kFrames = 31;
  const double truth_px = kSpeedPxPerFrame * (kFrames - 1);
  // From frame flows alone the 10% error sums: 6 px behind after 30 frames.
  EXPECT_NEAR(tracked_x_px(kFrames, 5, false), kFlowBias * truth_px, 1e-4);
  // Through keys every 5 frames: only the first key is placed by a (biased) flow.
  const double keyed = tracked_x_px(kFrames, 5, true);
  EXPECT_NEAR(keyed, truth_px, (1.0 - kFlowBias) * kSpeedPxPerFrame + 1e-4);
}

TEST(PursuitTracker, AKeyFrameItDidNotSeeIsNotAdopted) {
  // Frame 2 carries a key (frame 1) the tracker never saw: it was started after frame 1. The
  // tracker must not place a key it does not know, so it follows the flows until the next key.
  PursuitTracker tracker(intrinsics(), 0.1);
  const Eigen::Matrix3d R_WC = Eigen::Matrix3d::Identity();
  tracker.start(Eigen::Vector3d::UnitZ(), R_WC, kFramePeriodNs);
  perception::MotionResult motion = frame_motion(2, 5, true);
  motion.key_flow_x_px = 50.0f;  // Would move the target 50 px if the key were adopted.
  tracker.update(motion, R_WC, 2 * kFramePeriodNs);
  const Eigen::Vector3d d = tracker.direction_W(2 * kFramePeriodNs);
  EXPECT_NEAR(kFocalPx * d.x() / d.z(), kFlowBias * kSpeedPxPerFrame, 1e-4);
}

TEST(PursuitTracker, AFlowTheTargetCouldNotHaveMadeIsNotFollowed) {
  // Ten frames of a target moving 2 px a frame (3.4 deg/s at 500 px focal length), then one flow
  // of 30 px the other way (the fovea's window taken by a background sweeping past: 0.06 rad in
  // a frame, 103 deg/s of surprise), then the target's own flow again. The false reading is
  // neither placed nor turned into velocity; the target is where its true motion puts it.
  PursuitTracker tracker(intrinsics(), 0.1);
  const Eigen::Matrix3d R_WC = Eigen::Matrix3d::Identity();
  tracker.start(Eigen::Vector3d::UnitZ(), R_WC, 0);
  constexpr int kFrames = 14;
  constexpr int kFalse = 11;
  for (int n = 1; n <= kFrames; ++n) {
    perception::MotionResult motion;
    motion.frame = static_cast<std::uint64_t>(n);
    motion.valid = n > 1;
    motion.flow_x_px = n == kFalse ? -30.0f : static_cast<float>(kSpeedPxPerFrame);
    tracker.update(motion, R_WC, n * kFramePeriodNs);
  }
  const Eigen::Vector3d d = tracker.direction_W(kFrames * kFramePeriodNs);
  // Frame 11 extrapolates with the filtered velocity (short of 2 px while it converges).
  EXPECT_NEAR(kFocalPx * d.x() / d.z(), kSpeedPxPerFrame * (kFrames - 1), 1.0);
  EXPECT_EQ(tracker.extrapolated_frames(), 2u);  // Frame 1 (no flow yet) and the false one.
  EXPECT_GT(tracker.angular_velocity_W().y(), 0.0);
}

/// Frame n (1-based) of a still camera fixed on a target moving kSpeedPxPerFrame to the right
/// that the fovea sees as horizontal stripes: the motion reads no x at all (one-directional, the
/// gradient along y), while the fixated region's centre, `offset_px` right of the fixated point,
/// moves with the target.
void stripes_frame(int n, double offset_px, perception::MotionResult& motion,
                   perception::FixatedRegion& region) {
  motion = perception::MotionResult{};
  motion.frame = static_cast<std::uint64_t>(n);
  motion.valid = n > 1;
  motion.level = 0;
  motion.one_directional = true;
  motion.gradient_orientation_rad = static_cast<float>(0.5 * 3.141592653589793);
  region = perception::FixatedRegion{};
  region.valid = true;
  region.cells = 60;
  region.centroid_x_px = static_cast<float>(offset_px + kSpeedPxPerFrame * (n - 1));
}

double tracked_stripes_x_px(bool with_region) {
  PursuitTracker tracker(intrinsics(), 0.1);
  const Eigen::Matrix3d R_WC = Eigen::Matrix3d::Identity();
  constexpr double kOffsetPx = 12.0;
  perception::MotionResult motion;
  perception::FixatedRegion region;
  stripes_frame(1, kOffsetPx, motion, region);
  // Started where the region was seen with the target on the axis.
  tracker.start(Eigen::Vector3d::UnitZ(), R_WC, 0, region, {0, 0});
  constexpr int kFrames = 40;
  for (int n = 1; n <= kFrames; ++n) {
    stripes_frame(n, kOffsetPx, motion, region);
    if (!with_region) region.valid = false;
    tracker.update(motion, R_WC, n * kFramePeriodNs, region, {0, 0});
  }
  const Eigen::Vector3d d = tracker.direction_W(kFrames * kFramePeriodNs);
  return kFocalPx * d.x() / d.z();
}

TEST(PursuitTracker, AcrossStripesTheFixatedRegionPlacesTheTarget) {
  const double truth_px = kSpeedPxPerFrame * 39;
  // Motion alone says the target has not moved: the tracker stays (the old lag).
  EXPECT_NEAR(tracked_stripes_x_px(false), 0.0, 1e-6);
  // The region's centre, held at its offset from the target, brings it along.
  EXPECT_NEAR(tracked_stripes_x_px(true), truth_px, 0.1 * truth_px);
}

TEST(PursuitTracker, WhereTheFoveaSeesBothWaysTheRegionIsNotUsed) {
  // A textured fovea measures the motion; a region 30 px off changes nothing.
  PursuitTracker tracker(intrinsics(), 0.1);
  const Eigen::Matrix3d R_WC = Eigen::Matrix3d::Identity();
  tracker.start(Eigen::Vector3d::UnitZ(), R_WC, 0);
  perception::FixatedRegion region;
  region.valid = true;
  region.cells = 60;
  region.centroid_x_px = 30.0f;
  for (int n = 1; n <= 11; ++n) {
    tracker.update(frame_motion(n, 5, true), R_WC, n * kFramePeriodNs, region, {0, 0});
  }
  const Eigen::Vector3d d = tracker.direction_W(11 * kFramePeriodNs);
  EXPECT_NEAR(kFocalPx * d.x() / d.z(), kSpeedPxPerFrame * 10, 0.3);
  EXPECT_EQ(tracker.region_frames(), 0u);
}

}  // namespace
}  // namespace cambio::control
