// The attention behaviour on synthetic observations: salient peaks placed as directions in the
// world, rendered into a retina level through a pinhole camera that turns to wherever the
// behaviour saccades. Closed-form truth: the peaks are visited in descending saliency, each
// within a sample's angular size of its direction, and a peak inside the inhibition radius of a
// visited one is never visited.
#include "cambio/behaviour/attention_behaviour.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "recording_actions.hpp"

namespace cambio::behaviour {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct Peak {
  Eigen::Vector3d direction_W;
  float saliency;
};

using testing::RecordingActions;

// A 640 x 480 pinhole eye with one 16 x 16 retina level of 40 px blocks centred on the image.
class SyntheticWorld {
 public:
  SyntheticWorld() {
    camera_.name = "left_eye";
    camera_.intrinsics = {640, 480, 500.0, 500.0, 319.5, 239.5};
    frame_.summary.levels = 1;
    frame_.summary.geometry[0][0] = {40, 320 - 8 * 40, 240 - 8 * 40, 1.0f};
    frame_.maps[0] = perception::FeatureMaps(1, 1, 16, 16);
    frame_.maps[0].set_computed(1);
    names_ = {"log@1.4"};
  }

  // A peak at a pixel of the initial view (camera pose = identity).
  void add_peak_at_pixel(double u, double v, float saliency) {
    peaks_.push_back({ray(u, v), saliency});
  }
  Eigen::Vector3d ray(double u, double v) const {
    const auto& k = camera_.intrinsics;
    return X_WC_.linear() * Eigen::Vector3d((u - k.principal_x_px) / k.focal_x_px,
                                            (v - k.principal_y_px) / k.focal_y_px, 1.0)
                                .normalized();
  }

  // The frame the eye sees now: each peak at the sample nearest its projection.
  const Observation& observe(std::int64_t now_ns) {
    auto& maps = frame_.maps[0];
    std::fill(maps.map(0, 0), maps.map(0, 0) + 16 * 16, 0.0f);
    const auto& g = frame_.summary.geometry[0][0];
    const auto& k = camera_.intrinsics;
    for (const Peak& peak : peaks_) {
      const Eigen::Vector3d p_C = X_WC_.linear().transpose() * peak.direction_W;
      if (p_C.z() <= 0.0) continue;
      const double u = k.focal_x_px * p_C.x() / p_C.z() + k.principal_x_px;
      const double v = k.focal_y_px * p_C.y() / p_C.z() + k.principal_y_px;
      const long x = std::lround((u - g.origin_x_px + 0.5) / g.scale_px - 0.5);
      const long y = std::lround((v - g.origin_y_px + 0.5) / g.scale_px - 0.5);
      if (x < 0 || x >= 16 || y < 0 || y >= 16) continue;
      maps.map(0, 0)[y * 16 + x] = peak.saliency;
    }
    frame_.summary.sequence += 1;
    frame_.summary.stamp_ns = now_ns;
    status_.stamp_ns = now_ns;
    observation_.now_ns = now_ns;
    observation_.ssm = &frame_.summary;
    observation_.ssm_frame = &frame_;
    observation_.gaze = &status_;
    observation_.feature_map_names = names_;
    observation_.dominant_camera = &camera_;
    observation_.X_W_dominant_camera = X_WC_;
    return observation_;
  }

  // The head turns the eye onto the direction at once (a saccade that lands in one step).
  void saccade_to(const Eigen::Vector3d& direction_W) {
    const Eigen::Vector3d ray_C = X_WC_.linear().transpose() * direction_W;
    X_WC_.linear() =
        X_WC_.linear() *
        Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), ray_C).toRotationMatrix();
    status_.commands_applied += 1;
  }
  const Eigen::Isometry3d& X_WC() const { return X_WC_; }

 private:
  hal::CameraInfo camera_;
  perception::SsmFrame frame_;
  std::vector<std::string> names_;
  std::vector<Peak> peaks_;
  control::GazeStatus status_;
  Eigen::Isometry3d X_WC_ = Eigen::Isometry3d::Identity();
  Observation observation_;
};

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

TEST(AttentionBehaviourTest, VisitsPeaksInDescendingSaliencyAndNeverInsideTheInhibitionRadius) {
  SyntheticWorld world;
  // Placed so that each stays in view from every other (the border excluded).
  world.add_peak_at_pixel(200, 170, 9.0f);
  world.add_peak_at_pixel(440, 170, 7.0f);
  world.add_peak_at_pixel(220, 320, 5.0f);
  world.add_peak_at_pixel(420, 320, 3.0f);
  // 80 px (about 9 deg) above the strongest: inside its 12 deg radius, never visited.
  world.add_peak_at_pixel(200, 90, 8.0f);
  const std::vector<Eigen::Vector3d> expected = {world.ray(200, 170), world.ray(440, 170),
                                                 world.ray(220, 320), world.ray(420, 320)};

  AttentionParams params;
  params.inhibition_radius_rad = 12.0 * kDeg;
  params.dwell_s = 0.3;
  AttentionBehaviour attention(params);
  RecordingActions actions;
  std::vector<Eigen::Vector3d> visited;
  std::int64_t now_ns = 0;
  attention.start(world.observe(now_ns), actions);
  for (int step = 0; step < 100; ++step) {
    now_ns += 100'000'000;
    const std::size_t before = actions.saccades.size();
    attention.step(world.observe(now_ns), actions);
    if (actions.saccades.size() > before) {
      visited.push_back(actions.saccades.back());
      world.saccade_to(actions.saccades.back());
    }
  }
  ASSERT_EQ(visited.size(), expected.size()) << attention.status();
  // A sample is 40 px (4.6 deg) wide: a peak is found within half of one in each direction.
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_LT(angle_between(visited[i], expected[i]), 3.3 * kDeg) << "visit " << i;
  }
  for (std::size_t i = 0; i < visited.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_GT(angle_between(visited[i], visited[j]), params.inhibition_radius_rad);
    }
  }
  EXPECT_EQ(attention.saccades(), 4);
  EXPECT_EQ(actions.holds, 1);  // Nothing left: it holds once.
  EXPECT_NE(attention.status().find("every salient direction visited"), std::string::npos)
      << attention.status();
}

TEST(AttentionBehaviourTest, DwellsAfterLandingBeforeTheNextChoice) {
  SyntheticWorld world;
  world.add_peak_at_pixel(200, 140, 9.0f);
  world.add_peak_at_pixel(440, 160, 7.0f);
  AttentionParams params;
  params.dwell_s = 0.5;
  AttentionBehaviour attention(params);
  RecordingActions actions;
  std::vector<double> saccade_times_s;
  std::int64_t now_ns = 0;
  attention.start(world.observe(now_ns), actions);
  for (int step = 0; step < 30; ++step) {
    now_ns += 100'000'000;
    const std::size_t before = actions.saccades.size();
    attention.step(world.observe(now_ns), actions);
    if (actions.saccades.size() > before) {
      saccade_times_s.push_back(static_cast<double>(now_ns) * 1e-9);
      world.saccade_to(actions.saccades.back());
    }
  }
  ASSERT_EQ(saccade_times_s.size(), 2u);
  // Sent at 0.1 s, landed (seen) at 0.2 s, dwelt 0.5 s: the next at 0.7 s.
  EXPECT_NEAR(saccade_times_s[0], 0.1, 1e-9);
  EXPECT_NEAR(saccade_times_s[1], 0.7, 1e-9);
}

TEST(AttentionBehaviourTest, RemembersWhatItSawAndGoesBackOnceItIsOutOfView) {
  SyntheticWorld world;
  // 26 deg either side: from one, the other lies 52 deg away, beyond the 32 deg half-field.
  const Eigen::Vector3d left_W = world.ray(60, 240);
  const Eigen::Vector3d right_W = world.ray(580, 240);
  world.add_peak_at_pixel(60, 240, 9.0f);
  world.add_peak_at_pixel(580, 240, 7.0f);
  AttentionBehaviour attention(AttentionParams{});
  RecordingActions actions;
  std::int64_t now_ns = 0;
  attention.start(world.observe(now_ns), actions);
  for (int step = 0; step < 40; ++step) {
    now_ns += 100'000'000;
    const std::size_t before = actions.saccades.size();
    attention.step(world.observe(now_ns), actions);
    if (actions.saccades.size() > before) world.saccade_to(actions.saccades.back());
  }
  ASSERT_EQ(actions.saccades.size(), 2u) << attention.status();
  EXPECT_LT(angle_between(actions.saccades[0], left_W), 3.3 * kDeg);
  EXPECT_LT(angle_between(actions.saccades[1], right_W), 3.3 * kDeg);
}

TEST(AttentionBehaviourTest, AnUnknownMapIsAnErrorNamingTheMapsThereAre) {
  SyntheticWorld world;
  AttentionParams params;
  params.map = "log@9";
  AttentionBehaviour attention(params);
  try {
    (void)attention.candidates(world.observe(0));
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("'log@9'"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("log@1.4"), std::string::npos);
  }
}

TEST(AttentionBehaviourTest, ParamsReadFromTheExperimentFile) {
  BehaviourParams params({{"inhibition_radius_deg", {"10", "e.yaml:3"}},
                          {"dwell_s", {"0.25", "e.yaml:4"}},
                          {"map", {"sobel", "e.yaml:5"}}});
  const AttentionParams p = AttentionParams::from(params);
  EXPECT_NEAR(p.inhibition_radius_rad, 10.0 * kDeg, 1e-12);
  EXPECT_EQ(p.dwell_s, 0.25);
  EXPECT_EQ(p.map, "sobel");
  EXPECT_TRUE(params.unread_keys().empty());
  BehaviourParams bad({{"dwell_s", {"-1", "e.yaml:4"}}});
  EXPECT_THROW(AttentionParams::from(bad), std::invalid_argument);
}

}  // namespace
}  // namespace cambio::behaviour
