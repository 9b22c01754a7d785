#pragma once

// The pieces gaze_scene_generator.cpp builds a generated scene from: the run's random source,
// objects (shape, size, place, procedural texture, scripted motion) and their scene YAML. Not
// for other users: every draw's order is part of what a seed means.

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace cambio::app::gaze_scene {

inline constexpr double kDeg = std::numbers::pi / 180.0;
using Vec3 = std::array<double, 3>;

Vec3 add(const Vec3& a, const Vec3& b);
Vec3 scale(const Vec3& a, double s);

/// Unit direction at `azimuth` (positive left) and `elevation` (positive up), world frame.
Vec3 direction(double azimuth_rad, double elevation_rad);

/// Angle between two unit directions.
double angle_between(const Vec3& a, const Vec3& b);

/// Whether the segment from `from` to `to` passes within `radius_m` of `centre` (between its
/// ends): an object of that bounding radius there hides `to` from `from`.
bool blocks_segment(const Vec3& from, const Vec3& to, const Vec3& centre, double radius_m);

/// The radius of a sphere holding any generated object of `size_m` (a box's corner: sqrt(3)
/// half-sizes; a cylinder's rim, 1.25 radii from its middle: 1.6).
inline double bounding_radius_m(double size_m) {
  return std::sqrt(3.0) * size_m;
}

/// `value` as the YAML gives numbers: four decimals.
std::string number(double value);
std::string triple(const Vec3& v);

/// The run's random source: every draw of a generated run comes from here.
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : engine_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<>(lo, hi)(engine_); }
  /// Log-uniform: as many near targets (large, fast-changing disparities) as far ones.
  double log_uniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  int integer(int lo, int hi) { return std::uniform_int_distribution<>(lo, hi)(engine_); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  std::uint64_t seed() { return engine_(); }
  Vec3 colour() { return {uniform(0.15, 0.95), uniform(0.15, 0.95), uniform(0.15, 0.95)}; }

 private:
  std::mt19937_64 engine_;
};

struct Object {
  std::string name;
  std::string shape;  ///< sphere, box, cylinder
  double size_m = 0.05;
  Vec3 xyz_m{};
  bool textured = true;
  std::string motion;  ///< YAML of `motion:`, empty when static.
};

/// The object's entry in the scene's `objects:`, its colour and texture drawn; `texture_kind`,
/// when given, receives the texture's kind (noise, checker, dots, stripes) or "none".
std::string object_yaml(Draw& draw, const Object& o, std::string* texture_kind = nullptr);

/// A target: its angular radius (drawn, 2.5-6 deg) sets its size from its depth, so it covers
/// the retina's fovea at every depth without filling the field.
Object target_at(Draw& draw, const std::string& name, const Vec3& eye_W, double depth_m,
                 double azimuth_rad, double elevation_rad, bool textured);

/// 0-2 static objects elsewhere in the view, each at least 10 deg off every line of sight in
/// `keep_clear` (directions from the dominant eye): false matches for a wide coarse window.
void add_clutter(Draw& draw, const Vec3& eye_W, const std::vector<Vec3>& keep_clear,
                 std::vector<Object>& objects);

/// A textured wall behind everything (or, one run in five, none: sky and floor only), appended
/// to the scene's `objects:` YAML.
void add_backdrop(Draw& draw, double beyond_x_m, std::string& yaml);

/// A waypoint path through `points` at `times` (s after start_s).
std::string waypoints(double start_s, const std::vector<double>& times,
                      const std::vector<Vec3>& points);

}  // namespace cambio::app::gaze_scene
