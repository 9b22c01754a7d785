#include "gaze_scene_generator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "gaze_scene_objects.hpp"

namespace cambio::app {

namespace {

using gaze_scene::add;
using gaze_scene::direction;
using gaze_scene::Draw;
using gaze_scene::kDeg;
using gaze_scene::number;
using gaze_scene::Object;
using gaze_scene::scale;
using gaze_scene::target_at;
using gaze_scene::Vec3;

/// What the steps of generate_gaze_run build besides the run's truth. The steps draw in a fixed
/// order (target, task's objects, clutter, the objects' looks, backdrop): that order is what a
/// seed means.
struct RunPlan {
  Vec3 eye{};            ///< The dominant eye, world frame.
  Vec3 other_eye{};      ///< The verging eye.
  double depth = 0.0;    ///< The target's, from the dominant eye.
  double azimuth = 0.0;  ///< The target's (where it starts, for kPursuit), rad.
  double elevation = 0.0;
  std::vector<Object> objects;
  std::vector<Vec3> lines_of_sight;  ///< From the dominant eye; clutter keeps clear of them.
  double duration_s = 1.5;
  std::string commands;  ///< The experiment's `commands:` entries.
};

/// One stream per (seed, task, index): a run does not change when others are added.
std::uint64_t stream_seed(std::uint64_t bench_seed, GazeBenchTask task, int index) {
  std::seed_seq sequence{static_cast<std::uint32_t>(bench_seed),
                         static_cast<std::uint32_t>(bench_seed >> 32),
                         static_cast<std::uint32_t>(task), static_cast<std::uint32_t>(index)};
  std::array<std::uint32_t, 2> words{};
  sequence.generate(words.begin(), words.end());
  return (static_cast<std::uint64_t>(words[0]) << 32) | words[1];
}

/// The target: depth log-uniform over the range the issue sets, azimuth over the eyes' reach
/// with room for vergence, elevation +-20 deg.
RunPlan plan_target(Draw& draw, GazeBenchTask task, const Vec3& eye, GeneratedGazeRun& run) {
  RunPlan plan;
  plan.eye = eye;
  plan.depth =
      task == GazeBenchTask::kPursuit ? draw.log_uniform(0.8, 2.5) : draw.log_uniform(0.4, 3.0);
  plan.azimuth = draw.uniform(-25.0, 25.0) * kDeg;
  plan.elevation = draw.uniform(-20.0, 20.0) * kDeg;
  run.target_object = "target";
  run.target_depth_m = plan.depth;
  run.target_elevation_deg = plan.elevation / kDeg;
  plan.lines_of_sight.push_back(direction(plan.azimuth, plan.elevation));
  return plan;
}

/// kPursuit: a lateral arc at constant depth and elevation: constant angular speed seen from
/// the eye.
void add_pursuit_target(Draw& draw, RunPlan& plan, GeneratedGazeRun& run) {
  const Vec3& eye = plan.eye;
  const double speed = draw.uniform(5.0, 30.0) * kDeg;
  const double travel_s = 2.0;
  const double centre = draw.uniform(-10.0, 10.0) * kDeg;
  const double sign = draw.chance(0.5) ? 1.0 : -1.0;
  plan.azimuth = centre - sign * speed * travel_s / 2.0;
  run.pursuit_speed_deg_s = speed / kDeg;
  run.pursue_at_s = 0.9;
  Object target = target_at(draw, "target", eye, plan.depth, plan.azimuth, plan.elevation, true);
  std::vector<double> times;
  std::vector<Vec3> points;
  for (int k = 0; k <= 8; ++k) {
    const double t = travel_s * k / 8.0;
    times.push_back(t);
    points.push_back(
        add(eye, scale(direction(plan.azimuth + sign * speed * t, plan.elevation), plan.depth)));
  }
  target.motion = gaze_scene::waypoints(run.pursue_at_s, times, points);
  plan.objects.push_back(target);
  for (const Vec3& p : points) {
    const Vec3 d{p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]};
    plan.lines_of_sight.push_back(scale(d, 1.0 / plan.depth));
  }
  plan.duration_s = run.pursue_at_s + travel_s;
  plan.commands =
      "    - {at_s: 0.0, fixate: {object: target}}\n    - {at_s: " + number(run.pursue_at_s) +
      ", pursue: {}}\n";
}

/// Whether both eyes see both objects' centres: neither object (of its largest bounding radius)
/// stands between an eye and the other's centre. A near target can hide a far one from the
/// verging eye alone (12 cm of baseline), which would make the run's re-vergence impossible.
bool mutually_visible(const RunPlan& plan, const Vec3& a, double a_radius_m, const Vec3& b,
                      double b_radius_m) {
  for (const Vec3& eye : {plan.eye, plan.other_eye}) {
    if (gaze_scene::blocks_segment(eye, b, a, a_radius_m) ||
        gaze_scene::blocks_segment(eye, a, b, b_radius_m)) {
      return false;
    }
  }
  return true;
}

/// kSaccadeDepth: another depth (at least a factor 1.5 nearer or further: a vergence change of
/// 0.7 deg at 3 m, 5 deg at 0.4 m) and another direction, 10-30 deg away, where both eyes see
/// both objects.
void add_saccade_target(Draw& draw, RunPlan& plan, GeneratedGazeRun& run) {
  const double depth = plan.depth;
  double second = depth;
  while (std::max(second / depth, depth / second) < 1.5) second = draw.log_uniform(0.4, 3.0);
  double second_azimuth = plan.azimuth;
  double second_elevation = plan.elevation;
  const Object& first = plan.objects.front();
  // target_at draws the second's size below: its largest.
  const double second_radius_m = gaze_scene::bounding_radius_m(second * std::tan(6.0 * kDeg));
  for (int tries = 0; tries < 100; ++tries) {
    second_azimuth = draw.uniform(-25.0, 25.0) * kDeg;
    second_elevation = draw.uniform(-20.0, 20.0) * kDeg;
    const double apart = gaze_scene::angle_between(direction(plan.azimuth, plan.elevation),
                                                   direction(second_azimuth, second_elevation));
    const Vec3 second_W = add(plan.eye, scale(direction(second_azimuth, second_elevation), second));
    if (apart > 10.0 * kDeg && apart < 30.0 * kDeg &&
        mutually_visible(plan, first.xyz_m, gaze_scene::bounding_radius_m(first.size_m), second_W,
                         second_radius_m)) {
      break;
    }
  }
  run.second_depth_m = second;
  run.saccade_at_s = 1.0;
  plan.objects.push_back(
      target_at(draw, "second", plan.eye, second, second_azimuth, second_elevation, true));
  plan.lines_of_sight.push_back(direction(second_azimuth, second_elevation));
  plan.commands += "    - {at_s: " + number(run.saccade_at_s) + ", saccade: {object: second}}\n";
  plan.duration_s = run.saccade_at_s + 1.0;
}

/// kDistractors: objects crossing the line of sight in front of the target (occluding it for a
/// while) or behind it (seen beside it by the coarse levels), from 0.6 s, once the eyes have
/// verged.
void add_distractors(Draw& draw, RunPlan& plan, GeneratedGazeRun& run) {
  const double depth = plan.depth;
  run.distractors = draw.integer(1, 3);
  plan.duration_s = 3.0;
  for (int k = 0; k < run.distractors; ++k) {
    const bool in_front = depth > 0.7 && draw.chance(0.6);
    const double d = in_front ? draw.uniform(0.35, depth - 0.25) : depth + draw.uniform(0.3, 1.5);
    const double cross_s = draw.uniform(0.7, 2.2);
    const double speed_m_s = draw.uniform(0.2, 0.8);
    const double side = draw.chance(0.5) ? 1.0 : -1.0;
    const Vec3 on_line = add(plan.eye, scale(direction(plan.azimuth, plan.elevation), d));
    const Vec3 lateral{-std::sin(plan.azimuth) * side, std::cos(plan.azimuth) * side, 0.0};
    const Vec3 start = add(on_line, scale(lateral, -speed_m_s * cross_s));
    const Vec3 end = add(on_line, scale(lateral, speed_m_s * (plan.duration_s - cross_s)));
    Object o;
    o.name = "distractor_" + std::to_string(k);
    o.shape = "sphere";
    o.size_m = d * std::tan(draw.uniform(2.0, 5.0) * kDeg);
    o.xyz_m = start;
    o.motion = gaze_scene::waypoints(0.0, {0.0, plan.duration_s}, {start, end});
    plan.objects.push_back(o);
  }
}

// The scene's YAML; the run's target's shape and texture kind go into `run` (for the report).
std::string scene_yaml(Draw& draw, const RunPlan& plan, GeneratedGazeRun& run) {
  const std::string& name = run.name;
  std::string scene = "# Generated by cambio gaze-bench: " + name + "\nscene:\n  name: " + name +
                      "\n\nworld:\n  floor: true\n\nobjects:\n";
  double furthest_x = 0.0;
  for (const Object& o : plan.objects) {
    const bool target = o.name == run.target_object;
    scene += gaze_scene::object_yaml(draw, o, target ? &run.target_texture : nullptr);
    if (target) run.target_shape = o.shape;
    furthest_x = std::max(furthest_x, o.xyz_m[0] + 2.0 * o.size_m);
  }
  gaze_scene::add_backdrop(draw, std::max(furthest_x, plan.eye[0] + 1.0), scene);
  return scene;
}

std::string experiment_yaml(const RunPlan& plan, const GeneratedGazeRun& run,
                            const std::string& rig_path, const std::string& perception_path) {
  // The dominant (left) eye starts on the target, the other parallel to it. With eye tilt t
  // (positive down) then pan p, the optical axis is (cos t cos p, sin p, -sin t cos p).
  const Vec3 u = direction(plan.azimuth, plan.elevation);
  const double pan_deg = std::asin(std::clamp(u[1], -1.0, 1.0)) / kDeg;
  const double tilt_deg = std::atan2(-u[2], u[0]) / kDeg;
  std::string e =
      "# Generated by cambio gaze-bench: " + run.name + "\nexperiment:\n  name: " + run.name +
      "\n  rig: " + rig_path + "\n  scene: " + run.name + ".scene.yaml\n  executor: lockstep\n" +
      "  duration_s: " + number(plan.duration_s) + "\n  seed: " + std::to_string(run.seed) + "\n";
  if (!perception_path.empty()) e += "  perception: " + perception_path + "\n";
  e += "  task: gaze\n  initial_pose: {left_eye_pan_deg: " + number(pan_deg) +
       ", right_eye_pan_deg: " + number(pan_deg) + ", eye_tilt_deg: " + number(tilt_deg) + "}\n" +
       "  gaze:\n    dominant_eye: left\n  commands:\n" + plan.commands +
       "  evaluation:\n    settle: {disparity_px: 1.0, gaze_error_deg: 0.2}\n";
  // The saccade's second object is the target after it: judge each against the commanded one.
  if (run.task != GazeBenchTask::kSaccadeDepth) e += "    target_object: target\n";
  if (run.task == GazeBenchTask::kPursuit) e += "    pursuit_catch_up_s: 0.6\n";
  return e;
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
  Draw draw(stream_seed(bench_seed, task, index));
  run.seed = draw.seed() % 1'000'000 + 1;
  char name[64];
  std::snprintf(name, sizeof name, "%s_%03d", std::string(task_name(task)).c_str(), index);
  run.name = name;

  RunPlan plan = plan_target(draw, task, head.left_eye_W_m, run);
  plan.other_eye = head.right_eye_W_m;
  if (task == GazeBenchTask::kPursuit) {
    add_pursuit_target(draw, plan, run);
  } else {
    plan.objects.push_back(target_at(draw, "target", plan.eye, plan.depth, plan.azimuth,
                                     plan.elevation, task != GazeBenchTask::kUntextured));
    plan.commands = "    - {at_s: 0.0, fixate: {object: target}}\n";
  }
  run.target_azimuth_deg = plan.azimuth / kDeg;
  if (task == GazeBenchTask::kSaccadeDepth) add_saccade_target(draw, plan, run);
  if (task == GazeBenchTask::kDistractors) add_distractors(draw, plan, run);
  gaze_scene::add_clutter(draw, plan.eye, plan.lines_of_sight, plan.objects);

  run.scene_yaml = scene_yaml(draw, plan, run);
  run.experiment_yaml = experiment_yaml(plan, run, rig_path, perception_path);
  return run;
}

}  // namespace cambio::app
