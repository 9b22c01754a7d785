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
  p.min_saliency = params.number("min_saliency", p.min_saliency);
  p.max_visits = static_cast<int>(params.integer("max_visits", p.max_visits));
  require(!p.map.empty(), "map: expected a feature map's name, found ''");
  require(p.level >= -1, "level: expected a retina level >= 0, or -1 for the coarsest");
  require(p.inhibition_radius_rad > 0.0 && p.inhibition_radius_rad < std::numbers::pi,
          "inhibition_radius_deg: expected a value in (0, 180)");
  require(p.dwell_s >= 0.0, "dwell_s: expected a value >= 0");
  require(p.settled_error_px > 0.0, "settled_error_px: expected a value > 0");
  require(p.settle_timeout_s > 0.0, "settle_timeout_s: expected a value > 0");
  require(p.border_px >= 0.0, "border_px: expected a value >= 0");
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
  for (int y = 0; y < maps.height(); ++y) {
    for (int x = 0; x < maps.width(); ++x) {
      // The sample's centre in level-0 pixels (Retina's level_to_source).
      const double u = geometry.origin_x_px + (x + 0.5) * geometry.scale_px - 0.5;
      const double v = geometry.origin_y_px + (y + 0.5) * geometry.scale_px - 0.5;
      if (u < params_.border_px || v < params_.border_px ||
          u > k.width_px - 1 - params_.border_px || v > k.height_px - 1 - params_.border_px) {
        continue;
      }
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(maps.width()) +
                            static_cast<std::size_t>(x);
      const double saliency =
          sobel ? std::hypot(double{a[i]}, double{b[i]}) : std::abs(double{a[i]});
      if (!(saliency > params_.min_saliency)) continue;
      // Pinhole back-projection: the optical frame's ray through (u, v), then the base frame.
      const Eigen::Vector3d ray_C((u - k.principal_x_px) / k.focal_x_px,
                                  (v - k.principal_y_px) / k.focal_y_px, 1.0);
      out.push_back({saliency, u, v, (R_WC * ray_C).normalized()});
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const SalientSample& l, const SalientSample& r) {
    return l.saliency > r.saliency;
  });
  return out;
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
      observation.ssm_frame->summary.stamp_ns < landed_ns_) {
    return;
  }
  if (params_.max_visits > 0 && saccades_ >= params_.max_visits) {
    phase_ = Phase::kDone;
    done_reason_ = "made its " + std::to_string(params_.max_visits) + " visits";
    return;
  }
  for (const SalientSample& candidate : candidates(observation)) {
    if (inhibited(candidate.direction_W)) continue;
    const ActionResult sent = actions.saccade_to_pixel(candidate.u_px, candidate.v_px);
    // Visited once chosen: a target the saccade cannot reach is not chosen again and again.
    visited_W_.push_back(candidate.direction_W);
    if (!sent.sent) {
      last_ = "could not saccade to (" + std::to_string(static_cast<int>(candidate.u_px)) + ", " +
              std::to_string(static_cast<int>(candidate.v_px)) + "): " + sent.message;
      return;
    }
    ++saccades_;
    applied_before_ = observation.gaze->commands_applied;
    sent_ns_ = observation.now_ns;
    timed_out_ = false;
    phase_ = Phase::kSaccading;
    char text[96];
    std::snprintf(text, sizeof(text), "saccade %d to pixel (%.0f, %.0f), saliency %.3g, ",
                  saccades_, candidate.u_px, candidate.v_px, candidate.saliency);
    last_ = text + describe_direction(candidate.direction_W);
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
                     std::to_string(visited_W_.size()) + " directions visited; ";
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
