// The gaze experiments end to end on the simulator (rendered eyes, the SSM, the gaze loop, the
// joint loops, physics), scored by the simulator's ground truth: each shipped experiment must
// meet its own goals with its shipped seed, with other seeds, and with its targets moved
// elsewhere (the scene's objects and the start pose overridden). A goal missed makes `cambio run`
// exit 1; the summary's metrics are printed on failure.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "run_cambio.hpp"

namespace cambio {
namespace {

namespace fs = std::filesystem;

struct ExperimentCase {
  std::string label;       ///< Names the test and its output directory.
  std::string experiment;  ///< Under firmware_config/experiments/.
  std::string sets;        ///< Extra --set arguments.
};

std::ostream& operator<<(std::ostream& out, const ExperimentCase& c) {
  return out << c.label;
}

// The left eye's pan (deg) that looks at (x, y) from its pan axis at (0.04, 0.06) m with the
// neck straight (rigs/cambio.yaml): where a run "from parallel" starts both eyes.
std::string on_target_pose(double x_m, double y_m) {
  const double pan_deg = std::atan2(y_m - 0.06, x_m - 0.04) * 180.0 / std::numbers::pi;
  std::ostringstream sets;
  sets << "--set experiment.initial_pose.left_eye_pan_deg=" << pan_deg
       << " --set experiment.initial_pose.right_eye_pan_deg=" << pan_deg << " ";
  return sets.str();
}

std::string move_object(int index, const std::string& xyz) {
  return "--set 'scene.objects." + std::to_string(index) + ".xyz_m=" + xyz + "' ";
}

std::vector<ExperimentCase> cases() {
  std::vector<ExperimentCase> all;
  for (const char* name :
       {"vergence_sphere", "vergence_cube", "distractors", "saccade", "pursuit", "neck_rule"}) {
    all.push_back({std::string(name) + "_shipped", name, ""});
  }
  all.push_back({"vergence_sphere_seed_2", "vergence_sphere", "--set experiment.seed=2 "});
  all.push_back({"vergence_cube_seed_3", "vergence_cube", "--set experiment.seed=3 "});
  all.push_back({"distractors_seed_3", "distractors", "--set experiment.seed=3 "});
  all.push_back({"saccade_seed_2", "saccade", "--set experiment.seed=2 "});
  all.push_back({"pursuit_seed_2", "pursuit", "--set experiment.seed=2 "});
  all.push_back({"neck_rule_seed_2", "neck_rule", "--set experiment.seed=2 "});
  // Targets elsewhere: nearer, further, to the other side, above eye height.
  all.push_back({"vergence_sphere_ahead_further", "vergence_sphere",
                 move_object(0, "[1.1, 0.0, 1.40]") + on_target_pose(1.1, 0.0)});
  all.push_back({"vergence_sphere_near_left_high", "vergence_sphere",
                 move_object(0, "[0.9, 0.2, 1.45]") + on_target_pose(0.9, 0.2) +
                     "--set experiment.initial_pose.eye_tilt_deg=-3.3 "});
  all.push_back({"vergence_cube_further", "vergence_cube",
                 move_object(1, "[1.1, -0.05, 1.40]") + on_target_pose(1.1, -0.05)});
  all.push_back({"distractors_goal_moved", "distractors",
                 move_object(0, "[1.1, 0.1, 1.40]") + on_target_pose(1.1, 0.1)});
  all.push_back({"saccade_cubes_moved", "saccade",
                 move_object(0, "[1.0, 0.18, 1.40]") + move_object(1, "[1.2, -0.25, 1.40]") +
                     on_target_pose(1.0, 0.18)});
  all.push_back({"pursuit_further", "pursuit",
                 move_object(0, "[1.2, 0.35, 1.40]") +
                     "--set 'scene.objects.0.motion.waypoints=[{time_s: 0.0, xyz_m: [1.2, 0.35, "
                     "1.40]}, {time_s: 3.5, xyz_m: [1.2, -0.35, 1.40]}]' " +
                     on_target_pose(1.2, 0.35)});
  all.push_back(
      {"neck_rule_to_the_right", "neck_rule",
       move_object(0, "[0.771, -0.919, 1.40]") + move_object(1, "[0.771, -0.919, 0.65]")});
  return all;
}

class GazeExperiment : public ::testing::TestWithParam<ExperimentCase> {};

TEST_P(GazeExperiment, MeetsItsGoals) {
  const ExperimentCase& c = GetParam();
  const fs::path out = fs::temp_directory_path() / ("cambio_gaze_experiment_" + c.label);
  fs::remove_all(out);
  const auto result = testing::run_cambio("run firmware_config/experiments/" + c.experiment +
                                          ".yaml " + c.sets + "--out '" + out.string() + "'");
  ASSERT_TRUE(fs::exists(out / "summary.json")) << result.output;
  std::ifstream file(out / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(file);
  EXPECT_EQ(result.exit_code, 0) << result.output << "\nmetrics: " << summary["metrics"].dump()
                                 << "\ngoals: " << summary["goals"].dump();
  EXPECT_EQ(summary.at("passed"), true);
  EXPECT_FALSE(summary.at("goals").empty()) << "every gaze experiment names goals";
  for (const auto& [metric, goal] : summary.at("goals").items()) {
    EXPECT_TRUE(goal.at("passed").get<bool>()) << metric << ": " << goal.dump();
  }
  // What a run leaves for people: the trace, the plots, the key frames, believed and true joints.
  EXPECT_TRUE(fs::exists(out / "trace.csv"));
  EXPECT_TRUE(fs::exists(out / "plot_gaze.png"));
  EXPECT_TRUE(fs::exists(out / "plot_joints.png"));
  EXPECT_EQ(fs::exists(out / "plot_saccade.png"), c.experiment == "saccade");
  EXPECT_TRUE(summary.at("final_joints").contains("left_eye_pan"));
  EXPECT_TRUE(summary.at("final_joints").at("neck_pan").contains("believed_rad"));
  // No control loop allocates, the gaze loop's law included; only the trace and the sim's
  // camera loop (Mesa's renderer) say they may.
  for (const auto& loop : summary.at("loops")) {
    const std::string name = loop.at("name");
    const bool declared = name == "trace" || name == "camera";
    EXPECT_EQ(loop.at("allocation_exempt").get<bool>(), declared) << loop.dump();
    if (!declared) {
      EXPECT_EQ(loop.at("allocations").get<long long>(), 0) << loop.dump();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Experiments, GazeExperiment, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<ExperimentCase>& param_info) {
                           return param_info.param.label;
                         });

// Both eyes behind barrel lenses (a wide-angle USB camera's, the right one a little different):
// the sim renders through them (SimLens) and the SSM reads through them (Retina::set_lens), so
// the vergence experiment must end where the pinhole eyes end: the same verged pose to 0.05 deg,
// the same disparity to 0.1 px, its goals met.
TEST(GazeThroughLenses, VergesWhereThePinholeEyesVerge) {
  const std::string lenses =
      "--set 'rig.cameras.left_eye.distortion={k1: -0.28, k2: 0.07, p1: 0.001, p2: -0.0005, "
      "k3: 0}' --set 'rig.cameras.right_eye.distortion={k1: -0.25, k2: 0.07, p1: 0.001, p2: "
      "-0.0005, k3: 0}' ";
  nlohmann::json summaries[2];
  for (int through_lenses = 0; through_lenses < 2; ++through_lenses) {
    const fs::path out = fs::temp_directory_path() /
                         (through_lenses ? "cambio_gaze_through_lenses" : "cambio_gaze_pinhole");
    fs::remove_all(out);
    const auto result = testing::run_cambio(
        "run firmware_config/experiments/vergence_sphere.yaml " +
        (through_lenses ? lenses : std::string()) + "--out '" + out.string() + "'");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    std::ifstream file(out / "summary.json");
    summaries[through_lenses] = nlohmann::json::parse(file);
  }
  const auto degrees = [](const nlohmann::json& summary, const char* joint) {
    return summary.at("final_joints").at(joint).at("true_rad").get<double>() * 180.0 /
           std::numbers::pi;
  };
  for (const char* joint : {"left_eye_pan", "right_eye_pan", "eye_tilt"}) {
    EXPECT_NEAR(degrees(summaries[1], joint), degrees(summaries[0], joint), 0.05) << joint;
  }
  EXPECT_NEAR(summaries[1].at("metrics").at("final_disparity_px").get<double>(),
              summaries[0].at("metrics").at("final_disparity_px").get<double>(), 0.1);
  EXPECT_EQ(summaries[1].at("passed"), true) << summaries[1].at("goals").dump();
}

}  // namespace
}  // namespace cambio
