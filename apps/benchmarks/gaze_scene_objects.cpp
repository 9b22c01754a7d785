#include "gaze_scene_objects.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cambio::app::gaze_scene {

namespace {

/// BT.601 luma of a colour in [0, 1]: what the grey retina sees of it.
double luma(const Vec3& rgb) {
  return 0.299 * rgb[0] + 0.587 * rgb[1] + 0.114 * rgb[2];
}

/// A procedural texture over `base` with features of about `feature_m` (a fraction of the
/// object's size, so its image has detail at every depth), random kind and pattern seed, and a
/// second colour whose luma differs by 0.15-0.6 (two colours of one luma are no texture to a
/// grey retina: such a target is an untextured one, which has a task of its own).
std::string texture(Draw& draw, const Vec3& base, double feature_m,
                    std::string* drawn_kind = nullptr) {
  static constexpr const char* kKinds[] = {"noise", "checker", "dots", "stripes"};
  const char* kind = kKinds[draw.integer(0, 3)];
  if (drawn_kind != nullptr) *drawn_kind = kind;
  Vec3 second = draw.colour();
  for (int tries = 0; tries < 100; ++tries) {
    const double contrast = std::abs(luma(second) - luma(base));
    if (contrast >= 0.15 && contrast <= 0.6) break;
    second = draw.colour();
  }
  return std::string("{type: ") + kind + ", feature_size_m: " + number(feature_m) +
         ", second_rgb: " + triple(second) + ", seed: " + std::to_string(draw.seed() % 100000 + 1) +
         "}";
}

}  // namespace

Vec3 add(const Vec3& a, const Vec3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
Vec3 scale(const Vec3& a, double s) {
  return {a[0] * s, a[1] * s, a[2] * s};
}

Vec3 direction(double azimuth_rad, double elevation_rad) {
  return {std::cos(elevation_rad) * std::cos(azimuth_rad),
          std::cos(elevation_rad) * std::sin(azimuth_rad), std::sin(elevation_rad)};
}

double angle_between(const Vec3& a, const Vec3& b) {
  const double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  return std::acos(std::clamp(dot, -1.0, 1.0));
}

bool blocks_segment(const Vec3& from, const Vec3& to, const Vec3& centre, double radius_m) {
  const Vec3 along = add(to, scale(from, -1.0));
  const Vec3 to_centre = add(centre, scale(from, -1.0));
  const double length2 = along[0] * along[0] + along[1] * along[1] + along[2] * along[2];
  if (!(length2 > 0.0)) return false;
  const double t =
      (along[0] * to_centre[0] + along[1] * to_centre[1] + along[2] * to_centre[2]) / length2;
  if (t <= 0.0 || t >= 1.0) return false;
  const Vec3 nearest = add(from, scale(along, t));
  const Vec3 off = add(centre, scale(nearest, -1.0));
  return off[0] * off[0] + off[1] * off[1] + off[2] * off[2] < radius_m * radius_m;
}

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4f", value);
  return text;
}

std::string triple(const Vec3& v) {
  return "[" + number(v[0]) + ", " + number(v[1]) + ", " + number(v[2]) + "]";
}

std::string object_yaml(Draw& draw, const Object& o, std::string* texture_kind) {
  std::string y = "  - name: " + o.name + "\n    shape: " + o.shape + "\n";
  if (o.shape == "sphere") y += "    radius_m: " + number(o.size_m) + "\n";
  if (o.shape == "box") {
    y += "    size_m: " + triple({2 * o.size_m, 2 * o.size_m, 2 * o.size_m}) + "\n";
  }
  if (o.shape == "cylinder") {
    y += "    radius_m: " + number(o.size_m) + "\n    length_m: " + number(2.5 * o.size_m) + "\n";
  }
  const Vec3 rgb = draw.colour();
  y += "    xyz_m: " + triple(o.xyz_m) + "\n    rgb: " + triple(rgb) + "\n";
  if (texture_kind != nullptr) *texture_kind = "none";
  if (o.textured) {
    y += "    texture: " + texture(draw, rgb, o.size_m * draw.uniform(0.12, 0.35), texture_kind) +
         "\n";
  }
  if (!o.motion.empty()) y += "    body: scripted\n    motion: " + o.motion + "\n";
  return y;
}

Object target_at(Draw& draw, const std::string& name, const Vec3& eye_W, double depth_m,
                 double azimuth_rad, double elevation_rad, bool textured) {
  static constexpr const char* kShapes[] = {"sphere", "box", "cylinder"};
  Object o;
  o.name = name;
  o.shape = kShapes[draw.integer(0, 2)];
  o.size_m = depth_m * std::tan(draw.uniform(2.5, 6.0) * kDeg);
  o.xyz_m = add(eye_W, scale(direction(azimuth_rad, elevation_rad), depth_m));
  o.textured = textured;
  return o;
}

void add_clutter(Draw& draw, const Vec3& eye_W, const std::vector<Vec3>& keep_clear,
                 std::vector<Object>& objects) {
  const int count = draw.integer(0, 2);
  for (int k = 0, tries = 0; k < count && tries < 50; ++tries) {
    const double azimuth = draw.uniform(-40.0, 40.0) * kDeg;
    const double elevation = draw.uniform(-20.0, 20.0) * kDeg;
    const Vec3 u = direction(azimuth, elevation);
    bool clear = true;
    for (const Vec3& v : keep_clear) clear = clear && angle_between(u, v) > 10.0 * kDeg;
    if (!clear) continue;
    objects.push_back(target_at(draw, "clutter_" + std::to_string(k), eye_W,
                                draw.log_uniform(0.5, 3.0), azimuth, elevation, true));
    ++k;
  }
}

void add_backdrop(Draw& draw, double beyond_x_m, std::string& yaml) {
  if (draw.chance(0.2)) return;
  const double x = beyond_x_m + draw.uniform(0.3, 2.5);
  const Vec3 rgb = draw.colour();
  yaml += "  - name: backdrop\n    shape: box\n    size_m: [0.05, " + number(4.0 * x) + ", 4.0]\n" +
          "    xyz_m: " + triple({x, 0.0, 1.4}) + "\n    rgb: " + triple(rgb) +
          "\n    texture: " + texture(draw, rgb, draw.uniform(0.02, 0.15)) + "\n";
}

std::string waypoints(double start_s, const std::vector<double>& times,
                      const std::vector<Vec3>& points) {
  std::string y = "{type: waypoints, start_s: " + number(start_s) + ", waypoints: [";
  for (std::size_t k = 0; k < points.size(); ++k) {
    y += std::string(k ? ", " : "") + "{time_s: " + number(times[k]) +
         ", xyz_m: " + triple(points[k]) + "}";
  }
  return y + "]}";
}

}  // namespace cambio::app::gaze_scene
