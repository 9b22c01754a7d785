#include "gaze_scene_generator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <stdexcept>

namespace cambio::app {

namespace {

using std::numbers::pi;
constexpr double kDeg = pi / 180.0;
using Vec3 = std::array<double, 3>;

Vec3 add(const Vec3& a, const Vec3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
Vec3 scale(const Vec3& a, double s) {
  return {a[0] * s, a[1] * s, a[2] * s};
}

/// Unit direction at `azimuth` (positive left) and `elevation` (positive up), world frame.
Vec3 direction(double azimuth_rad, double elevation_rad) {
  return {std::cos(elevation_rad) * std::cos(azimuth_rad),
          std::cos(elevation_rad) * std::sin(azimuth_rad), std::sin(elevation_rad)};
}

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4f", value);
  return text;
}

std::string triple(const Vec3& v) {
  return "[" + number(v[0]) + ", " + number(v[1]) + ", " + number(v[2]) + "]";
}

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

/// BT.601 luma of a colour in [0, 1]: what the grey retina sees of it.
double luma(const Vec3& rgb) {
  return 0.299 * rgb[0] + 0.587 * rgb[1] + 0.114 * rgb[2];
}

/// A procedural texture over `base` with features of about `feature_m` (a fraction of the
/// object's size, so its image has detail at every depth), random kind and pattern seed, and a
/// second colour whose luma differs by 0.15-0.6 (two colours of one luma are no texture to a
/// grey retina: such a target is an untextured one, which has a task of its own).
std::string texture(Draw& draw, const Vec3& base, double feature_m) {
  static constexpr const char* kKinds[] = {"noise", "checker", "dots", "stripes"};
  const char* kind = kKinds[draw.integer(0, 3)];
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

struct Object {
  std::string name;
  std::string shape;  ///< sphere, box, cylinder
  double size_m = 0.05;
  Vec3 xyz_m{};
  bool textured = true;
  std::string motion;  ///< YAML of `motion:`, empty when static.
};

std::string object_yaml(Draw& draw, const Object& o) {
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
  if (o.textured) {
    y += "    texture: " + texture(draw, rgb, o.size_m * draw.uniform(0.12, 0.35)) + "\n";
  }
  if (!o.motion.empty()) y += "    body: scripted\n    motion: " + o.motion + "\n";
  return y;
}

/// A target: `angular_radius` sets its size from its depth, so it covers the retina's fovea at
/// every depth without filling the field.
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

/// Angle between two unit directions.
double angle_between(const Vec3& a, const Vec3& b) {
  const double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  return std::acos(std::clamp(dot, -1.0, 1.0));
}

/// 0-2 static objects elsewhere in the view, each at least 10 deg off every line of sight in
/// `keep_clear` (directions from the dominant eye): false matches for a wide coarse window.
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

/// A textured wall behind everything (or, one run in five, none: sky and floor only).
void add_backdrop(Draw& draw, double beyond_x_m, std::vector<Object>& objects, std::string& yaml) {
  if (draw.chance(0.2)) return;
  const double x = beyond_x_m + draw.uniform(0.3, 2.5);
  (void)objects;
  const Vec3 rgb = draw.colour();
  yaml += "  - name: backdrop\n    shape: box\n    size_m: [0.05, " + number(4.0 * x) + ", 4.0]\n" +
          "    xyz_m: " + triple({x, 0.0, 1.4}) + "\n    rgb: " + triple(rgb) +
          "\n    texture: " + texture(draw, rgb, draw.uniform(0.02, 0.15)) + "\n";
}

/// A waypoint path through `points` at `times` (s after start_s).
std::string waypoints(double start_s, const std::vector<double>& times,
                      const std::vector<Vec3>& points) {
  std::string y = "{type: waypoints, start_s: " + number(start_s) + ", waypoints: [";
  for (std::size_t k = 0; k < points.size(); ++k) {
    y += std::string(k ? ", " : "") + "{time_s: " + number(times[k]) +
         ", xyz_m: " + triple(points[k]) + "}";
  }
  return y + "]}";
}

}  // namespace

std::string_view task_name(GazeBenchTask task) {
  switch (task) {
    case GazeBenchTask::kVerge:
      return "verge";
    case GazeBenchTask::kSaccadeDepth:
      return "saccade_depth";
    case GazeBenchTask::kDistractors:
      return "distractors";
    case GazeBenchTask::kPursuit:
      return "pursuit";
    case GazeBenchTask::kUntextured:
      return "untextured";
  }
  return "unknown";
}

GeneratedGazeRun generate_gaze_run(GazeBenchTask task, int index, std::uint64_t bench_seed,
                                   const HeadGeometry& head, const std::string& rig_path,
                                   const std::string& perception_path) {
  GeneratedGazeRun run;
  run.task = task;
  run.index = index;
  // One stream per (seed, task, index): a run does not change when others are added.
  std::seed_seq sequence{static_cast<std::uint32_t>(bench_seed),
                         static_cast<std::uint32_t>(bench_seed >> 32),
                         static_cast<std::uint32_t>(task), static_cast<std::uint32_t>(index)};
  std::uint64_t stream_seed = 0;
  {
    std::array<std::uint32_t, 2> words{};
    sequence.generate(words.begin(), words.end());
    stream_seed = (static_cast<std::uint64_t>(words[0]) << 32) | words[1];
  }
  Draw draw(stream_seed);
  run.seed = draw.seed() % 1'000'000 + 1;
  char name[64];
  std::snprintf(name, sizeof name, "%s_%03d", std::string(task_name(task)).c_str(), index);
  run.name = name;

  const Vec3& eye = head.left_eye_W_m;
  std::vector<Object> objects;
  double duration_s = 1.5;
  std::string commands;

  // The target: depth log-uniform over the range the issue sets, azimuth over the eyes' reach
  // with room for vergence, elevation +-20 deg.
  const double depth =
      task == GazeBenchTask::kPursuit ? draw.log_uniform(0.8, 2.5) : draw.log_uniform(0.4, 3.0);
  double azimuth = draw.uniform(-25.0, 25.0) * kDeg;
  const double elevation = draw.uniform(-20.0, 20.0) * kDeg;
  run.target_object = "target";
  run.target_depth_m = depth;
  run.target_elevation_deg = elevation / kDeg;
  std::vector<Vec3> lines_of_sight{direction(azimuth, elevation)};

  if (task == GazeBenchTask::kPursuit) {
    // A lateral arc at constant depth and elevation: constant angular speed seen from the eye.
    const double speed = draw.uniform(5.0, 30.0) * kDeg;
    const double travel_s = 2.0;
    const double centre = draw.uniform(-10.0, 10.0) * kDeg;
    const double sign = draw.chance(0.5) ? 1.0 : -1.0;
    azimuth = centre - sign * speed * travel_s / 2.0;
    run.pursuit_speed_deg_s = speed / kDeg;
    run.pursue_at_s = 0.9;
    Object target = target_at(draw, "target", eye, depth, azimuth, elevation, true);
    std::vector<double> times;
    std::vector<Vec3> points;
    for (int k = 0; k <= 8; ++k) {
      const double t = travel_s * k / 8.0;
      times.push_back(t);
      points.push_back(add(eye, scale(direction(azimuth + sign * speed * t, elevation), depth)));
    }
    target.motion = waypoints(run.pursue_at_s, times, points);
    objects.push_back(target);
    for (const Vec3& p : points) {
      const Vec3 d{p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]};
      lines_of_sight.push_back(scale(d, 1.0 / depth));
    }
    duration_s = run.pursue_at_s + travel_s;
    commands =
        "    - {at_s: 0.0, fixate: {object: target}}\n    - {at_s: " + number(run.pursue_at_s) +
        ", pursue: {}}\n";
  } else {
    objects.push_back(target_at(draw, "target", eye, depth, azimuth, elevation,
                                task != GazeBenchTask::kUntextured));
    commands = "    - {at_s: 0.0, fixate: {object: target}}\n";
  }
  run.target_azimuth_deg = azimuth / kDeg;

  if (task == GazeBenchTask::kSaccadeDepth) {
    // Another depth (at least a factor 1.5 nearer or further: a vergence change of 0.7 deg at
    // 3 m, 5 deg at 0.4 m) and another direction, 10-30 deg away.
    double second = depth;
    while (std::max(second / depth, depth / second) < 1.5) second = draw.log_uniform(0.4, 3.0);
    double second_azimuth = azimuth;
    double second_elevation = elevation;
    for (int tries = 0; tries < 100; ++tries) {
      second_azimuth = draw.uniform(-25.0, 25.0) * kDeg;
      second_elevation = draw.uniform(-20.0, 20.0) * kDeg;
      const double apart =
          angle_between(direction(azimuth, elevation), direction(second_azimuth, second_elevation));
      if (apart > 10.0 * kDeg && apart < 30.0 * kDeg) break;
    }
    run.second_depth_m = second;
    run.saccade_at_s = 1.0;
    objects.push_back(
        target_at(draw, "second", eye, second, second_azimuth, second_elevation, true));
    lines_of_sight.push_back(direction(second_azimuth, second_elevation));
    commands += "    - {at_s: " + number(run.saccade_at_s) + ", saccade: {object: second}}\n";
    duration_s = run.saccade_at_s + 1.0;
  }

  if (task == GazeBenchTask::kDistractors) {
    // Objects crossing the line of sight in front of the target (occluding it for a while) or
    // behind it (seen beside it by the coarse levels), from 0.6 s, once the eyes have verged.
    run.distractors = draw.integer(1, 3);
    duration_s = 3.0;
    for (int k = 0; k < run.distractors; ++k) {
      const bool in_front = depth > 0.7 && draw.chance(0.6);
      const double d = in_front ? draw.uniform(0.35, depth - 0.25) : depth + draw.uniform(0.3, 1.5);
      const double cross_s = draw.uniform(0.7, 2.2);
      const double speed_m_s = draw.uniform(0.2, 0.8);
      const double side = draw.chance(0.5) ? 1.0 : -1.0;
      const Vec3 on_line = add(eye, scale(direction(azimuth, elevation), d));
      const Vec3 lateral{-std::sin(azimuth) * side, std::cos(azimuth) * side, 0.0};
      const Vec3 start = add(on_line, scale(lateral, -speed_m_s * cross_s));
      const Vec3 end = add(on_line, scale(lateral, speed_m_s * (duration_s - cross_s)));
      Object o;
      o.name = "distractor_" + std::to_string(k);
      o.shape = "sphere";
      o.size_m = d * std::tan(draw.uniform(2.0, 5.0) * kDeg);
      o.xyz_m = start;
      o.motion = waypoints(0.0, {0.0, duration_s}, {start, end});
      objects.push_back(o);
    }
  }

  add_clutter(draw, eye, lines_of_sight, objects);

  std::string scene = "# Generated by cambio gaze-bench: " + run.name +
                      "\nscene:\n  name: " + run.name + "\n\nworld:\n  floor: true\n\nobjects:\n";
  double furthest_x = 0.0;
  for (const Object& o : objects) {
    scene += object_yaml(draw, o);
    furthest_x = std::max(furthest_x, o.xyz_m[0] + 2.0 * o.size_m);
  }
  add_backdrop(draw, std::max(furthest_x, eye[0] + 1.0), objects, scene);
  run.scene_yaml = scene;

  // The dominant (left) eye starts on the target, the other parallel to it. With eye tilt t
  // (positive down) then pan p, the optical axis is (cos t cos p, sin p, -sin t cos p).
  const Vec3 u = direction(azimuth, elevation);
  const double pan_deg = std::asin(std::clamp(u[1], -1.0, 1.0)) / kDeg;
  const double tilt_deg = std::atan2(-u[2], u[0]) / kDeg;
  std::string e =
      "# Generated by cambio gaze-bench: " + run.name + "\nexperiment:\n  name: " + run.name +
      "\n  rig: " + rig_path + "\n  scene: " + run.name + ".scene.yaml\n  executor: lockstep\n" +
      "  duration_s: " + number(duration_s) + "\n  seed: " + std::to_string(run.seed) + "\n";
  if (!perception_path.empty()) e += "  perception: " + perception_path + "\n";
  e += "  task: gaze\n  initial_pose: {left_eye_pan_deg: " + number(pan_deg) +
       ", right_eye_pan_deg: " + number(pan_deg) + ", eye_tilt_deg: " + number(tilt_deg) + "}\n" +
       "  gaze:\n    dominant_eye: left\n  commands:\n" + commands +
       "  evaluation:\n    settle: {disparity_px: 1.0, gaze_error_deg: 0.2}\n";
  // The saccade's second object is the target after it: judge each against the commanded one.
  if (task != GazeBenchTask::kSaccadeDepth) e += "    target_object: target\n";
  if (task == GazeBenchTask::kPursuit) e += "    pursuit_catch_up_s: 0.6\n";
  run.experiment_yaml = e;
  return run;
}

}  // namespace cambio::app
