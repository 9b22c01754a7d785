#include "cambio/sim/object_motion.hpp"

#include <cmath>
#include <numbers>

namespace cambio::sim {

std::array<double, 3> scripted_position(const config::SceneObjectConfig& object,
                                        double t_s) noexcept {
  const auto& motion = object.motion;
  const auto& p0 = object.pose.xyz_m;
  const double t = t_s - motion.start_s;
  switch (motion.kind) {
    case config::MotionKind::kNone:
      return p0;
    case config::MotionKind::kWaypoints: {
      const auto& points = motion.waypoints;
      if (points.empty()) return p0;
      if (t <= points.front().time_s) return points.front().xyz_m;
      for (std::size_t i = 1; i < points.size(); ++i) {
        if (t <= points[i].time_s) {
          const double s = (t - points[i - 1].time_s) / (points[i].time_s - points[i - 1].time_s);
          std::array<double, 3> p{};
          for (int k = 0; k < 3; ++k) {
            p[k] = points[i - 1].xyz_m[k] + s * (points[i].xyz_m[k] - points[i - 1].xyz_m[k]);
          }
          return p;
        }
      }
      return points.back().xyz_m;
    }
    case config::MotionKind::kOscillate: {
      if (t <= 0.0) return p0;
      const double offset =
          motion.amplitude_m * std::sin(2 * std::numbers::pi * t / motion.period_s);
      return {p0[0] + offset * motion.axis[0], p0[1] + offset * motion.axis[1],
              p0[2] + offset * motion.axis[2]};
    }
    case config::MotionKind::kCircle: {
      // Two unit vectors spanning the plane normal to the axis; the circle starts at p0 + r u
      // minus r u, i.e. the object begins on its scene pose and circles a centre r away.
      const auto& n = motion.axis;
      std::array<double, 3> helper =
          std::abs(n[2]) < 0.9 ? std::array<double, 3>{0, 0, 1} : std::array<double, 3>{1, 0, 0};
      std::array<double, 3> u{n[1] * helper[2] - n[2] * helper[1],
                              n[2] * helper[0] - n[0] * helper[2],
                              n[0] * helper[1] - n[1] * helper[0]};
      const double norm = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
      for (auto& c : u) c /= norm;
      const std::array<double, 3> v{n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2],
                                    n[0] * u[1] - n[1] * u[0]};
      const double angle = t <= 0.0 ? 0.0 : 2 * std::numbers::pi * t / motion.period_s;
      const double a = motion.radius_m * (std::cos(angle) - 1.0);
      const double b = motion.radius_m * std::sin(angle);
      return {p0[0] + a * u[0] + b * v[0], p0[1] + a * u[1] + b * v[1],
              p0[2] + a * u[2] + b * v[2]};
    }
  }
  return p0;
}

}  // namespace cambio::sim
