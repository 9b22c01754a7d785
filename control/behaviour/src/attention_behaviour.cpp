#include "cambio/behaviour/attention_behaviour.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

namespace cambio::behaviour {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

int map_index(const Observation& observation, std::string_view name) {
  for (std::size_t i = 0; i < observation.feature_map_names.size(); ++i) {
    if (observation.feature_map_names[i] == name) return static_cast<int>(i);
  }
  std::string known;
  for (const auto& entry : observation.feature_map_names) {
    known += (known.empty() ? "" : ", ") + entry;
  }
  throw std::invalid_argument("attention: the SSM computes no map '" + std::string(name) +
                              "' (it computes: " + (known.empty() ? "none" : known) + ")");
}

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("behaviour.params.") + what);
}

// Azimuth (positive to the robot's left) and elevation (positive up) of a base-frame direction,
// for status lines a person reads.
std::string describe_direction(const Eigen::Vector3d& d_W) {
  char text[64];
  std::snprintf(text, sizeof(text), "az %+.1f deg el %+.1f deg",
                std::atan2(d_W.y(), d_W.x()) * kDegPerRad,
                std::atan2(d_W.z(), std::hypot(d_W.x(), d_W.y())) * kDegPerRad);
  return text;
}

}  // namespace

AttentionParams AttentionParams::from(BehaviourParams& params) {
  AttentionParams p;
  p.map = params.text("map", p.map);
  p.level = static_cast<int>(params.integer("level", p.level));
  p.inhibition_radius_rad =
      params.number("inhibition_radius_deg", p.inhibition_radius_rad * kDegPerRad) / kDegPerRad;
  p.dwell_s = params.number("dwell_s", p.dwell_s);
  p.settled_error_px = params.number("settled_error_px", p.settled_error_px);
  p.settle_timeout_s = params.number("settle_timeout_s", p.settle_timeout_s);
  p.border_px = params.number("border_px", p.border_px);
  p.min_elevation_rad =
      params.number("min_elevation_deg", p.min_elevation_rad * kDegPerRad) / kDegPerRad;
  p.min_saliency = params.number("min_saliency", p.min_saliency);
  p.target_depth_m = params.number("target_depth_m", p.target_depth_m);
  p.max_visits = static_cast<int>(params.integer("max_visits", p.max_visits));
  require(!p.map.empty(), "map: expected a feature map's name, found ''");
  require(p.level >= -1, "level: expected a retina level >= 0, or -1 for the coarsest");
  require(p.inhibition_radius_rad > 0.0 && p.inhibition_radius_rad < std::numbers::pi,
          "inhibition_radius_deg: expected a value in (0, 180)");
  require(p.dwell_s >= 0.0, "dwell_s: expected a value >= 0");
  require(p.settled_error_px > 0.0, "settled_error_px: expected a value > 0");
  require(p.settle_timeout_s > 0.0, "settle_timeout_s: expected a value > 0");
  require(p.border_px >= 0.0, "border_px: expected a value >= 0");
  require(
      p.min_elevation_rad >= -std::numbers::pi / 2 && p.min_elevation_rad < std::numbers::pi / 2,
      "min_elevation_deg: expected a value in [-90, 90)");
  require(p.target_depth_m > 0.0, "target_depth_m: expected a distance > 0");
  require(p.min_saliency >= 0.0, "min_saliency: expected a value >= 0");
  require(p.max_visits >= 0, "max_visits: expected a count >= 0 (0: no limit)");
  return p;
}

AttentionBehaviour::AttentionBehaviour(AttentionParams params) : params_(std::move(params)) {}

std::vector<SalientSample> AttentionBehaviour::candidates(const Observation& observation) const {
  std::vector<SalientSample> out;
  if (observation.ssm_frame == nullptr || observation.dominant_camera == nullptr) return out;
  const auto eye = static_cast<std::size_t>(observation.dominant_eye);
  const perception::SsmFrame& frame = *observation.ssm_frame;
  const perception::FeatureMaps& maps = frame.maps[eye];
  const bool sobel = params_.map == "sobel";
  const int first = map_index(observation, sobel ? "sobel_x" : params_.map);
  const int second = sobel ? map_index(observation, "sobel_y") : first;
  const int levels = std::min(frame.summary.levels, maps.levels());
  const int level = params_.level < 0 ? levels - 1 : params_.level;
  if (level < 0 || level >= levels) {
    throw std::invalid_argument("attention: no retina level " + std::to_string(level) +
                                " (the SSM has " + std::to_string(levels) + ")");
  }
  for (const int map : {first, second}) {
    if ((maps.computed() >> map & 1U) == 0) return out;  // Not computed this frame: nothing seen.
  }
  const perception::LevelGeometry& geometry =
      frame.summary.geometry[eye][static_cast<std::size_t>(level)];
  const hal::CameraIntrinsics& k = observation.dominant_camera->intrinsics;
  const Eigen::Matrix3d& R_WC = observation.X_W_dominant_camera.linear();
  const float* a = maps.map(level, first);
  const float* b = maps.map(level, second);
  const int w = maps.width();
  const int h = maps.height();
  const auto saliency_at = [&](int x, int y) {
    const std::size_t i =
        static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
    return sobel ? std::hypot(double{a[i]}, double{b[i]}) : std::abs(double{a[i]});
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      // The sample's centre in level-0 pixels (Retina's level_to_source).
      const double u = geometry.origin_x_px + (x + 0.5) * geometry.scale_px - 0.5;
      const double v = geometry.origin_y_px + (y + 0.5) * geometry.scale_px - 0.5;
      if (u < params_.border_px || v < params_.border_px ||
          u > k.width_px - 1 - params_.border_px || v > k.height_px - 1 - params_.border_px) {
        continue;
      }
      const double saliency = saliency_at(x, y);
      if (!(saliency > params_.min_saliency)) continue;
      // One candidate per blob: its peak, not the samples on its flanks.
      bool peak = true;
      for (int dy = -1; dy <= 1 && peak; ++dy) {
        for (int dx = -1; dx <= 1 && peak; ++dx) {
          const int nx = x + dx;
          const int ny = y + dy;
          if ((dx != 0 || dy != 0) && nx >= 0 && nx < w && ny >= 0 && ny < h) {
            peak = saliency_at(nx, ny) <= saliency;
          }
        }
      }
      if (!peak) continue;
      // Pinhole back-projection: the optical frame's ray through (u, v), then the base frame.
      const Eigen::Vector3d ray_C((u - k.principal_x_px) / k.focal_x_px,
                                  (v - k.principal_y_px) / k.focal_y_px, 1.0);
      const Eigen::Vector3d direction_W = (R_WC * ray_C).normalized();
      if (std::asin(std::clamp(direction_W.z(), -1.0, 1.0)) < params_.min_elevation_rad) continue;
      out.push_back({saliency, u, v, direction_W});
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const SalientSample& l, const SalientSample& r) {
    return l.saliency > r.saliency;
  });
  return out;
}

void AttentionBehaviour::remember(const Observation& observation,
                                  const std::vector<SalientSample>& seen) {
  const auto& k = observation.dominant_camera->intrinsics;
  const Eigen::Matrix3d R_CW = observation.X_W_dominant_camera.linear().transpose();
  // In view: where a response would have been a candidate, a sample's width inside the border
  // (a response between the last sample and the border is seen by neither).
  const auto eye = static_cast<std::size_t>(observation.dominant_eye);
  const int levels =
      std::min(observation.ssm_frame->summary.levels, observation.ssm_frame->maps[eye].levels());
  const int level = params_.level < 0 ? levels - 1 : params_.level;
  const double margin_px =
      params_.border_px +
      observation.ssm_frame->summary.geometry[eye][static_cast<std::size_t>(level)].scale_px;
  const double cos_radius = std::cos(params_.inhibition_radius_rad);
  // What is in view now is seen afresh: an old entry there is replaced by what is seen near it,
  // or dropped if nothing salient is there any more. Entries out of view are kept.
  std::vector<SalientSample> kept;
  for (const SalientSample& old : memory_) {
    const Eigen::Vector3d d_C = R_CW * old.direction_W;
    const double u = k.focal_x_px * d_C.x() / d_C.z() + k.principal_x_px;
    const double v = k.focal_y_px * d_C.y() / d_C.z() + k.principal_y_px;
    const bool in_view = d_C.z() > 0.0 && u >= margin_px && v >= margin_px &&
                         u <= k.width_px - 1 - margin_px && v <= k.height_px - 1 - margin_px;
    const bool seen_again = std::any_of(seen.begin(), seen.end(), [&](const SalientSample& now) {
      return now.direction_W.dot(old.direction_W) >= cos_radius;
    });
    if (!in_view && !seen_again) kept.push_back(old);
  }
  kept.insert(kept.end(), seen.begin(), seen.end());
  std::stable_sort(kept.begin(), kept.end(), [](const SalientSample& l, const SalientSample& r) {
    return l.saliency > r.saliency;
  });
  memory_ = std::move(kept);
}

bool AttentionBehaviour::inhibited(const Eigen::Vector3d& direction_W) const {
  const double cos_radius = std::cos(params_.inhibition_radius_rad);
  return std::any_of(visited_W_.begin(), visited_W_.end(), [&](const Eigen::Vector3d& seen) {
    return seen.dot(direction_W) >= cos_radius;
  });
}

void AttentionBehaviour::start(const Observation& observation, Actions& actions) {
  (void)actions;
  // What it looks at when it starts is already attended to.
  visited_W_.push_back(observation.X_W_dominant_camera.linear().col(2).normalized());
  last_ = "started looking " + describe_direction(visited_W_.back());
}

void AttentionBehaviour::choose(const Observation& observation, Actions& actions) {
  // The map must show the scene as seen since the gaze landed (not mid-saccade).
  if (observation.ssm_frame == nullptr || observation.gaze == nullptr ||
      observation.dominant_camera == nullptr ||
      observation.ssm_frame->summary.stamp_ns < landed_ns_) {
    return;
  }
  if (params_.max_visits > 0 && saccades_ >= params_.max_visits) {
    phase_ = Phase::kDone;
    done_reason_ = "made its " + std::to_string(params_.max_visits) + " visits";
    return;
  }
  remember(observation, candidates(observation));
  // The most salient direction remembered that has not been visited: in view or seen before.
  const auto best = std::find_if(memory_.begin(), memory_.end(), [&](const SalientSample& seen) {
    return !inhibited(seen.direction_W);
  });
  if (best != memory_.end()) {
    const SalientSample target = *best;
    // A point on the ray from the eye's optical centre: the eye turns onto the direction
    // whatever the depth (the other eye verges from its disparity).
    const Eigen::Vector3d p_W =
        observation.X_W_dominant_camera.translation() + params_.target_depth_m * target.direction_W;
    const ActionResult sent = actions.saccade_to_point(p_W);
    // Visited once chosen: a target the saccade cannot reach is not chosen again and again.
    visited_W_.push_back(target.direction_W);
    if (!sent.sent) {
      last_ = "could not saccade " + describe_direction(target.direction_W) + ": " + sent.message;
      return;
    }
    ++saccades_;
    applied_before_ = observation.gaze->commands_applied;
    sent_ns_ = observation.now_ns;
    timed_out_ = false;
    phase_ = Phase::kSaccading;
    char text[64];
    std::snprintf(text, sizeof(text), "saccade %d, saliency %.3g, to ", saccades_, target.saliency);
    last_ = text + describe_direction(target.direction_W);
    return;
  }
  phase_ = Phase::kDone;
  done_reason_ = "every salient direction visited";
  (void)actions.hold();
}

void AttentionBehaviour::step(const Observation& observation, Actions& actions) {
  switch (phase_) {
    case Phase::kChoosing:
      choose(observation, actions);
      break;
    case Phase::kSaccading: {
      if (observation.gaze == nullptr) break;
      const control::GazeStatus& gaze = *observation.gaze;
      const bool taken = gaze.commands_applied > applied_before_;
      const bool landed =
          taken && !gaze.saccade_active && gaze.feature_error_px <= params_.settled_error_px;
      const bool late =
          static_cast<double>(observation.now_ns - sent_ns_) * 1e-9 > params_.settle_timeout_s;
      if (landed || late) {
        timed_out_ = !landed;
        landed_ns_ = observation.now_ns;
        phase_ = Phase::kDwelling;
      }
      break;
    }
    case Phase::kDwelling:
      if (static_cast<double>(observation.now_ns - landed_ns_) * 1e-9 >= params_.dwell_s) {
        phase_ = Phase::kChoosing;
        choose(observation, actions);
      }
      break;
    case Phase::kDone:
      break;
  }
}

std::string AttentionBehaviour::status() const {
  std::string line = "attention: " + std::to_string(saccades_) + " saccades, " +
                     std::to_string(visited_W_.size()) + " directions visited, " +
                     std::to_string(memory_.size()) + " remembered; ";
  switch (phase_) {
    case Phase::kChoosing:
      line += "choosing; last: " + last_;
      break;
    case Phase::kSaccading:
      line += last_;
      break;
    case Phase::kDwelling:
      line += std::string(timed_out_ ? "dwelling (saccade did not settle in time) after "
                                     : "dwelling after ") +
              last_;
      break;
    case Phase::kDone:
      line += "done: " + done_reason_ + "; last: " + last_;
      break;
  }
  return line;
}

void register_builtin_behaviours(BehaviourRegistry& registry) {
  registry.add("attention", [](BehaviourParams& params) {
    return std::make_unique<AttentionBehaviour>(AttentionParams::from(params));
  });
}

}  // namespace cambio::behaviour
