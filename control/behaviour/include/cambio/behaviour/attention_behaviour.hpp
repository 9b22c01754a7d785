#pragma once

#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cambio/behaviour/behaviour.hpp"
#include "cambio/behaviour/registry.hpp"

namespace cambio::behaviour {

/// `attention`'s parameters (the experiment's behaviour.params; every key optional).
struct AttentionParams {
  /// The feature map whose magnitude is the saliency ("sobel": the Sobel gradient's magnitude
  /// from sobel_x and sobel_y); any name of firmware_config/perception's operator set.
  std::string map = "log@1.4";
  /// The retina level searched; -1: the coarsest (the one that covers the field).
  int level = -1;
  /// A direction within this angle of a visited one is not visited again (inhibition of return).
  double inhibition_radius_rad = 0.14;
  /// How long the gaze stays on what it reached before the next choice.
  double dwell_s = 0.5;
  /// The saccade has landed when the gaze loop reports no saccade and an image error below this.
  double settled_error_px = 3.0;
  /// A saccade that has not landed after this long counts as landed (a target out of reach).
  double settle_timeout_s = 2.0;
  /// Samples whose centre lies closer than this to the image's edge are not candidates (their
  /// operators see the image's replicated border).
  double border_px = 24.0;
  /// Directions below this elevation in the base frame are not candidates: the robot's own arms
  /// and grippers lie there, as salient as anything (-pi/2: none excluded).
  double min_elevation_rad = -std::numbers::pi / 2;
  /// Responses at or below this are not worth a look.
  double min_saliency = 0.0;
  /// Where on a chosen direction the saccade's target point is put (m): the dominant eye turns
  /// onto the direction whatever it is; the other eye starts verged there and corrects from
  /// its disparity.
  double target_depth_m = 1.5;
  /// Stop after this many saccades (0: never).
  int max_visits = 0;

  /// Reads them from `params`; throws std::invalid_argument for a value out of range.
  static AttentionParams from(BehaviourParams& params);
};

/// A candidate the saliency map offers: a retina sample of the dominant eye.
struct SalientSample {
  double saliency = 0.0;
  double u_px = 0.0;  ///< Its centre in the dominant eye's image (level-0 pixels).
  double v_px = 0.0;
  Eigen::Vector3d direction_W = Eigen::Vector3d::UnitX();  ///< Unit, robot base frame.
};

/// An attention system (the paper's future work): scans the scene by saccading to the most
/// salient retina response it has not visited yet. Saliency is the magnitude of one feature map
/// on one retina level of the dominant eye; each local maximum's sample centre (LevelGeometry)
/// becomes a direction in the base frame through the eye's intrinsics and believed pose.
/// Directions within inhibition_radius of one visited before are suppressed (inhibition of
/// return in the world, so a target stays visited whatever the head does). What it has seen is
/// remembered by direction, so a response seen from an earlier view and now out of the field is
/// still a candidate; what is in view is seen afresh each time. After a saccade lands
/// (GazeStatus: no saccade, image error <= settled_error_px) it dwells dwell_s, then chooses
/// again from a frame taken after it landed. The direction it starts looking in counts as
/// visited. Made for a still scene: remembered directions do not follow moving objects.
class AttentionBehaviour final : public Behaviour {
 public:
  explicit AttentionBehaviour(AttentionParams params);

  void start(const Observation& observation, Actions& actions) override;
  void step(const Observation& observation, Actions& actions) override;
  std::string status() const override;

  /// The candidates of one observation (local maxima of the saliency), most salient first, not
  /// yet filtered by inhibition.
  /// Throws std::invalid_argument when the map is not among the observation's feature maps.
  std::vector<SalientSample> candidates(const Observation& observation) const;
  /// The directions visited (the start's first), base frame.
  const std::vector<Eigen::Vector3d>& visited_W() const { return visited_W_; }
  int saccades() const { return saccades_; }

 private:
  enum class Phase : std::uint8_t { kChoosing, kSaccading, kDwelling, kDone };

  bool inhibited(const Eigen::Vector3d& direction_W) const;
  /// Merges what one observation shows (`seen`, most salient first) into memory_.
  void remember(const Observation& observation, const std::vector<SalientSample>& seen);
  void choose(const Observation& observation, Actions& actions);

  AttentionParams params_;
  Phase phase_ = Phase::kChoosing;
  std::vector<Eigen::Vector3d> visited_W_;
  std::vector<SalientSample> memory_;  // Most salient first.
  int saccades_ = 0;
  std::uint64_t applied_before_ = 0;  // GazeStatus::commands_applied when the saccade was sent.
  std::int64_t sent_ns_ = 0;
  std::int64_t landed_ns_ = 0;
  bool timed_out_ = false;
  std::string last_;  // What it did last, for status().
  std::string done_reason_;
};

/// Registers the program's built-in behaviours (`attention`).
void register_builtin_behaviours(BehaviourRegistry& registry);

}  // namespace cambio::behaviour
