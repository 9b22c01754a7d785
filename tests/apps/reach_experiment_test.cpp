// The reach experiment end to end on the simulator: the head saccades to a cube and verges on it,
// the nearer arm reaches what the head fixates (its stereo estimate), touches and grasps, scored
// by the ground truth. It must meet its goals (touch within 3 s, the gripper within 1 cm of the
// surface) on several seeds and with the cube moved to either arm's side, and refuse a cube out
// of reach with the reason, failing its goals with exit 1 rather than crashing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "run_cambio.hpp"

namespace cambio {
namespace {

namespace fs = std::filesystem;

struct ReachCase {
  std::string label;
  double x_m, y_m, z_m;  ///< The cube's centre; its post runs from the floor to under it.
  int seed;
  const char* arm;  ///< The arm that should reach (the nearer shoulder).
};

std::ostream& operator<<(std::ostream& out, const ReachCase& c) {
  return out << c.label;
}

std::string cube_at(double x_m, double y_m, double z_m) {
  const double post_m = z_m - 0.03;  // Up to the cube's bottom face (a 6 cm cube).
  std::ostringstream sets;
  sets << std::setprecision(6) << "--set 'scene.objects.0.xyz_m=[" << x_m << ", " << y_m << ", "
       << z_m << "]' --set 'scene.objects.1.xyz_m=[" << x_m << ", " << y_m << ", " << post_m / 2
       << "]' --set scene.objects.1.length_m=" << post_m << " ";
  return sets.str();
}

struct ReachRun {
  testing::CommandResult result;
  nlohmann::json summary;
};

ReachRun run_reach(const std::string& label, const std::string& sets) {
  const fs::path out = fs::temp_directory_path() / ("cambio_reach_experiment_" + label);
  fs::remove_all(out);
  ReachRun run;
  run.result = testing::run_cambio("run firmware_config/experiments/reach_touch.yaml " + sets +
                                   "--out '" + out.string() + "'");
  if (fs::exists(out / "summary.json")) {
    std::ifstream file(out / "summary.json");
    run.summary = nlohmann::json::parse(file);
  }
  return run;
}

class ReachExperiment : public ::testing::TestWithParam<ReachCase> {};

TEST_P(ReachExperiment, TouchesAndGraspsWithinItsGoals) {
  const ReachCase& c = GetParam();
  const ReachRun run = run_reach(c.label, cube_at(c.x_m, c.y_m, c.z_m) + "--set experiment.seed=" +
                                              std::to_string(c.seed) + " ");
  ASSERT_FALSE(run.summary.is_null()) << run.result.output;
  const nlohmann::json& summary = run.summary;
  EXPECT_EQ(run.result.exit_code, 0)
      << run.result.output << "\nmetrics: " << summary["metrics"].dump()
      << "\narms: " << summary["arms"].dump();
  EXPECT_EQ(summary.at("passed"), true);
  const nlohmann::json& metrics = summary.at("metrics");
  ASSERT_TRUE(metrics.contains("time_to_touch_s")) << summary.dump();
  EXPECT_LE(metrics.at("time_to_touch_s").get<double>(), 3.0);
  EXPECT_LE(metrics.at("touch_position_error_m").get<double>(), 0.01);
  // The head's stereo estimate, against where its dominant eye truly looked: a few mm.
  EXPECT_LE(metrics.at("estimated_target_error_m").get<double>(), 0.01);
  const nlohmann::json& arm = summary.at("arms").at("arms").at(c.arm);
  EXPECT_EQ(arm.at("phase"), "touching") << summary.at("arms").dump();
  EXPECT_EQ(arm.at("gripper_closed"), true) << "the gripper closes after the touch";
  EXPECT_TRUE(summary.at("arms").at("refusal").is_null());
  // No control loop allocates, the arm's and the gaze's laws included, reaching or not.
  for (const auto& loop : summary.at("loops")) {
    const std::string name = loop.at("name");
    if (name == "arm" || name == "control" || name.starts_with("joint")) {
      EXPECT_FALSE(loop.at("allocation_exempt").get<bool>()) << loop.dump();
      EXPECT_EQ(loop.at("allocations").get<long long>(), 0) << loop.dump();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Positions, ReachExperiment,
    ::testing::Values(ReachCase{"shipped", 0.48, -0.14, 1.08, 1, "right"},
                      ReachCase{"right_low_seed_2", 0.45, -0.25, 1.00, 2, "right"},
                      ReachCase{"middle_left_seed_3", 0.50, 0.05, 1.10, 3, "left"},
                      ReachCase{"near_left_shoulder", 0.42, 0.20, 1.05, 1, "left"}),
    [](const ::testing::TestParamInfo<ReachCase>& param_info) { return param_info.param.label; });

TEST(ReachExperimentRefusal, OutOfReachIsRefusedWithTheReasonAndFailsItsGoals) {
  const ReachRun run = run_reach("out_of_reach", cube_at(1.0, -0.14, 1.08));
  ASSERT_FALSE(run.summary.is_null()) << run.result.output;
  EXPECT_EQ(run.result.exit_code, 1) << run.result.output;
  EXPECT_EQ(run.summary.at("passed"), false);
  const std::string refusal = run.summary.at("arms").at("refusal").get<std::string>();
  EXPECT_NE(refusal.find("out of reach"), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("right_arm"), std::string::npos) << "the nearer arm's reason";
  EXPECT_EQ(run.summary.at("arms").at("arms").at("right").at("phase"), "refused");
  const nlohmann::json& goal = run.summary.at("goals").at("time_to_touch_s");
  EXPECT_EQ(goal.at("passed"), false);
  EXPECT_NE(goal.at("reason").get<std::string>().find("refused: out of reach"), std::string::npos)
      << goal.dump();
  EXPECT_NE(run.result.output.find("out of reach"), std::string::npos);
}

// Without goals, the script is the experiment's task: a reach the arms refused exited 0 with the
// refusal only in summary.json.
TEST(ReachExperimentRefusal, AGoalLessScriptWhoseReachIsRefusedDoesNotComplete) {
  const ReachRun run = run_reach("goal_less",
                                 "--set 'experiment.goals={}' --set experiment.duration_s=0.6 "
                                 "--set 'experiment.evaluation.key_frames_s=[0.5]' "
                                 "--set 'experiment.commands=[{at_s: 0.1, reach: [2, 0, 1]}]' ");
  ASSERT_FALSE(run.summary.is_null()) << run.result.output;
  EXPECT_EQ(run.result.exit_code, 1) << run.result.output;
  EXPECT_EQ(run.summary.at("outcome"), "commands_refused");
  EXPECT_NE(run.result.output.find("cambio run: the arms refused a command: out of reach"),
            std::string::npos)
      << run.result.output;
}

}  // namespace
}  // namespace cambio
