// `cambio gaze-bench`: the generator's scenes are what it says they are (deterministic, loadable,
// the target where the truth puts it), and a 20-scene subset runs end to end with every run
// scored against the simulator's truth. The full figures (hundreds of scenes) are a benchmark,
// run by hand (README); here the subset's rates guard against a collapse, not a percent.
#include "gaze_scene_generator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>

#include <nlohmann/json.hpp>

#include "cambio/config/experiment_config.hpp"
#include "cambio/config/shipped_config.hpp"
#include "gaze_bench_summary.hpp"
#include "run_cambio.hpp"

namespace cambio::app {
namespace {

namespace fs = std::filesystem;

TEST(GazeSceneGenerator, TheSameSeedGivesTheSameRunAndAnotherSeedAnother) {
  const std::string rig = config::find_shipped_config("rigs/cambio.yaml");
  for (const GazeBenchTask task : kGazeBenchTasks) {
    const GeneratedGazeRun a = generate_gaze_run(task, 3, 42, HeadGeometry{}, rig, "");
    const GeneratedGazeRun b = generate_gaze_run(task, 3, 42, HeadGeometry{}, rig, "");
    const GeneratedGazeRun c = generate_gaze_run(task, 3, 43, HeadGeometry{}, rig, "");
    EXPECT_EQ(a.scene_yaml, b.scene_yaml) << task_name(task);
    EXPECT_EQ(a.experiment_yaml, b.experiment_yaml) << task_name(task);
    EXPECT_NE(a.scene_yaml, c.scene_yaml) << task_name(task);
  }
}

TEST(GazeSceneGenerator, EveryRunLoadsAndItsTargetIsWhereTheTruthSays) {
  const std::string rig = config::find_shipped_config("rigs/cambio.yaml");
  const fs::path dir = fs::temp_directory_path() / "cambio_gaze_generator_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const HeadGeometry head;
  for (const GazeBenchTask task : kGazeBenchTasks) {
    for (int k = 0; k < 25; ++k) {
      const GeneratedGazeRun run = generate_gaze_run(task, k, 5, head, rig, "");
      std::ofstream(dir / (run.name + ".scene.yaml")) << run.scene_yaml;
      std::ofstream(dir / (run.name + ".yaml")) << run.experiment_yaml;
      const config::ExperimentConfig experiment =
          config::load_experiment((dir / (run.name + ".yaml")).string());
      ASSERT_TRUE(experiment.scene.has_value()) << run.name;
      const config::SceneObjectConfig* target = experiment.scene->find_object("target");
      ASSERT_NE(target, nullptr) << run.name;
      EXPECT_GE(run.target_depth_m, 0.4) << run.name;
      EXPECT_LE(run.target_depth_m, 3.0) << run.name;
      EXPECT_LE(std::abs(run.target_elevation_deg), 20.0) << run.name;
      // The report's shape and texture of the target are the loaded scene's.
      static const std::map<config::ShapeKind, std::string> kShapes = {
          {config::ShapeKind::kSphere, "sphere"},
          {config::ShapeKind::kBox, "box"},
          {config::ShapeKind::kCylinder, "cylinder"}};
      static const std::map<config::TextureKind, std::string> kTextures = {
          {config::TextureKind::kNone, "none"},
          {config::TextureKind::kNoise, "noise"},
          {config::TextureKind::kChecker, "checker"},
          {config::TextureKind::kDots, "dots"},
          {config::TextureKind::kStripes, "stripes"}};
      EXPECT_EQ(run.target_shape, kShapes.at(target->shape)) << run.name;
      EXPECT_EQ(run.target_texture, kTextures.at(target->texture.kind)) << run.name;
      if (task == GazeBenchTask::kPursuit) continue;  // It starts where its path starts.
      const auto& p = target->pose.xyz_m;
      const double depth = std::hypot(p[0] - head.left_eye_W_m[0], p[1] - head.left_eye_W_m[1],
                                      p[2] - head.left_eye_W_m[2]);
      EXPECT_NEAR(depth, run.target_depth_m, 1e-3) << run.name;
      EXPECT_NEAR(std::atan2(p[1] - head.left_eye_W_m[1], p[0] - head.left_eye_W_m[0]) * 180.0 /
                      std::numbers::pi,
                  run.target_azimuth_deg, 0.01)
          << run.name;
      if (task == GazeBenchTask::kSaccadeDepth) {
        EXPECT_GE(std::max(run.second_depth_m / run.target_depth_m,
                           run.target_depth_m / run.second_depth_m),
                  1.5)
            << run.name;
      }
    }
  }
  fs::remove_all(dir);
}

/// Whether `p` lies inside the loaded object's shape (axis-aligned, as the generator places
/// them: no rotation).
bool inside(const config::SceneObjectConfig& o, const std::array<double, 3>& p) {
  const auto& c = o.pose.xyz_m;
  const double dx = p[0] - c[0], dy = p[1] - c[1], dz = p[2] - c[2];
  switch (o.shape) {
    case config::ShapeKind::kSphere:
      return std::hypot(dx, dy, dz) < o.size_m[0] / 2;
    case config::ShapeKind::kBox:
      return std::abs(dx) < o.size_m[0] / 2 && std::abs(dy) < o.size_m[1] / 2 &&
             std::abs(dz) < o.size_m[2] / 2;
    case config::ShapeKind::kCylinder:
      return std::hypot(dx, dy) < o.size_m[0] / 2 && std::abs(dz) < o.size_m[1] / 2;
    default:
      ADD_FAILURE() << "unexpected shape";
      return false;
  }
}

/// Whether `blocker` stands between `eye` and `target`'s centre (points along the segment).
bool hidden_by(const std::array<double, 3>& eye, const config::SceneObjectConfig& target,
               const config::SceneObjectConfig& blocker) {
  const auto& t = target.pose.xyz_m;
  for (int i = 1; i < 400; ++i) {
    const double s = i / 400.0;
    const std::array<double, 3> p{eye[0] + s * (t[0] - eye[0]), eye[1] + s * (t[1] - eye[1]),
                                  eye[2] + s * (t[2] - eye[2])};
    if (inside(blocker, p)) return true;
  }
  return false;
}

TEST(GazeSceneGenerator, BothEyesSeeBothObjectsOfASaccadeAcrossDepths) {
  // A near target can hide a far one from the verging eye alone; re-verging on it would be
  // impossible, not a failure of the vision. Checked on the loaded scenes' shapes.
  const std::string rig = config::find_shipped_config("rigs/cambio.yaml");
  const fs::path dir = fs::temp_directory_path() / "cambio_gaze_saccade_visibility_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const HeadGeometry head;
  for (int k = 0; k < 150; ++k) {
    const GeneratedGazeRun run =
        generate_gaze_run(GazeBenchTask::kSaccadeDepth, k, 2026, head, rig, "");
    std::ofstream(dir / (run.name + ".scene.yaml")) << run.scene_yaml;
    std::ofstream(dir / (run.name + ".yaml")) << run.experiment_yaml;
    const config::ExperimentConfig experiment =
        config::load_experiment((dir / (run.name + ".yaml")).string());
    const config::SceneObjectConfig* first = experiment.scene->find_object("target");
    const config::SceneObjectConfig* second = experiment.scene->find_object("second");
    ASSERT_NE(first, nullptr) << run.name;
    ASSERT_NE(second, nullptr) << run.name;
    for (const auto& eye : {head.left_eye_W_m, head.right_eye_W_m}) {
      EXPECT_FALSE(hidden_by(eye, *second, *first)) << run.name;
      EXPECT_FALSE(hidden_by(eye, *first, *second)) << run.name;
    }
  }
  fs::remove_all(dir);
}

TEST(GazeBench, ATwentySceneSubsetRunsAndIsScoredAgainstTheTruth) {
  const auto result =
      testing::run_cambio("gaze-bench --scenes 4 --seed 11 --json", testing::Capture::kStdout);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto summary = nlohmann::json::parse(result.output, nullptr, false);
  ASSERT_FALSE(summary.is_discarded()) << result.output;
  ASSERT_EQ(summary["runs"].size(), 20u);
  for (const auto& run : summary["runs"]) {
    EXPECT_FALSE(run.contains("error")) << run.dump();
  }
  for (const char* task : {"verge", "saccade_depth", "distractors", "pursuit", "untextured"}) {
    ASSERT_TRUE(summary["tasks"].contains(task)) << task;
    EXPECT_EQ(summary["tasks"][task]["runs"], 4) << task;
  }
  // Every run is counted once under its target's texture.
  for (const auto& task : summary["tasks"].items()) {
    int runs = 0;
    for (const auto& kind : task.value()["by_target_texture"].items()) {
      runs += kind.value()["runs"].get<int>();
    }
    EXPECT_EQ(runs, task.value()["runs"].get<int>()) << task.key();
  }
  EXPECT_TRUE(summary["tasks"]["untextured"]["by_target_texture"].contains("none"));
  // Every failed run is counted once under how it ended.
  for (const auto& task : summary["tasks"].items()) {
    const auto& t = task.value();
    const auto& failed = t["failed_runs"];
    EXPECT_EQ(failed["never_verged"].get<int>() + failed["drawn_off_target"].get<int>() +
                  failed["short_of_goal"].get<int>(),
              t["runs"].get<int>() - t["successes"].get<int>() - t["errors"].get<int>())
        << task.key();
  }
  // Textured vergence and re-vergence across depths: the behaviour the bench exists for.
  EXPECT_GE(summary["tasks"]["verge"]["successes"].get<int>(), 3) << result.output;
  EXPECT_GE(summary["tasks"]["saccade_depth"]["successes"].get<int>(), 3) << result.output;
  int measurements = 0;
  for (const auto& bin : summary["confidence_calibration"]) {
    measurements += bin["measurements"].get<int>();
  }
  EXPECT_GT(measurements, 100) << "every run's disparities are compared with the truth";
}

/// One run's JSON as gaze_bench_runs.cpp writes it, with the fields the summary reads.
Json untextured_run(const char* name, bool success, Json first_verged_s,
                    double longest_off_target_s) {
  return Json{{"name", name},
              {"task", "untextured"},
              {"success", success},
              {"failure", success ? "" : "not verged at the end"},
              {"target_texture", "none"},
              {"verged_at_s", success ? Json(0.2) : Json(nullptr)},
              {"first_verged_s", first_verged_s},
              {"final_error_deg", 1.0},
              {"worst_error_deg", 2.0},
              {"pursuit_rms_deg", nullptr},
              {"off_target_s", longest_off_target_s},
              {"longest_off_target_s", longest_off_target_s},
              {"occluded_s", 0.0},
              {"calibration", Json::array()}};
}

TEST(GazeBenchSummary, FailedRunsAreToldApartByHowTheyEnded) {
  const std::vector<Json> runs{
      untextured_run("met", true, 0.1, 0.0),
      untextured_run("held_parallel", false, nullptr, 0.0),
      untextured_run("drawn_off", false, 0.1, 0.5),
      untextured_run("a_little_off", false, 0.1, 0.05),
      untextured_run("just_within_the_bound", false, 0.1, 0.1),
  };
  const Json t = summarise_gaze_bench(runs, 1, 5)["tasks"]["untextured"];
  EXPECT_EQ(t["successes"], 1);
  EXPECT_EQ(t["failed_runs"]["never_verged"], 1);
  EXPECT_EQ(t["failed_runs"]["drawn_off_target"], 1);
  EXPECT_EQ(t["failed_runs"]["short_of_goal"], 2);
  // Pursuit is judged by its RMS error, not by when the verging eye first verged.
  Json pursuit = untextured_run("pursuit_rms", false, nullptr, 0.0);
  pursuit["task"] = "pursuit";
  pursuit["pursuit_rms_deg"] = 1.5;
  const Json p = summarise_gaze_bench({pursuit}, 1, 1)["tasks"]["pursuit"];
  EXPECT_EQ(p["failed_runs"]["never_verged"], 0);
  EXPECT_EQ(p["failed_runs"]["short_of_goal"], 1);
}

}  // namespace
}  // namespace cambio::app
