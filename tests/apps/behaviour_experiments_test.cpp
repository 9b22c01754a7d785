// Behaviours in whole runs of `cambio run`: the shipped attention_scan visits every object of its
// scene (ground truth: the dominant eye's true optical axis resting on each), a plugin's
// behaviour that throws fails the run while it keeps going holding, and a misspelt parameter is
// refused at its line before anything runs.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "run_cambio.hpp"

namespace cambio {
namespace {

namespace fs = std::filesystem;

nlohmann::json read_summary(const fs::path& out) {
  std::ifstream file(out / "summary.json");
  return nlohmann::json::parse(file);
}

// An experiment on the attention_scan scene with `behaviour` (YAML lines at its indentation),
// written into `folder`.
// clang-format off
fs::path write_experiment(const fs::path& folder, const std::string& behaviour) {
  fs::create_directories(folder);
  const std::string config = std::string(CAMBIO_SOURCE_DIR) + "/firmware_config";
  const std::string text = "experiment:\n"                                           // 1
                           "  name: plugin_run\n"                                    // 2
                           "  rig: " + config + "/rigs/cambio.yaml\n"                // 3
                           "  scene: " + config + "/scenes/attention_scan.yaml\n"    // 4
                           "  perception: " + config + "/perception/vergence.yaml\n" // 5
                           "  duration_s: 1.0\n"                                      // 6
                           "  task: gaze\n"                                          // 7
                           "  behaviour:\n" + behaviour;                             // 8
  std::ofstream(folder / "experiment.yaml") << text;
  return folder / "experiment.yaml";
}
// clang-format on

// Runs attention_scan with `sets` and checks that it visited every object of the scene.
void expect_every_object_visited(const std::string& label, const std::string& sets) {
  const fs::path out = fs::temp_directory_path() / ("cambio_behaviour_" + label);
  fs::remove_all(out);
  const auto result = testing::run_cambio("run firmware_config/experiments/attention_scan.yaml " +
                                          sets + "--out '" + out.string() + "'");
  ASSERT_TRUE(fs::exists(out / "summary.json")) << result.output;
  const nlohmann::json summary = read_summary(out);
  EXPECT_EQ(result.exit_code, 0) << result.output << "\nvisits: " << summary["visits"].dump()
                                 << "\nbehaviour: " << summary["behaviour"].dump();
  EXPECT_EQ(summary.at("metrics").at("objects_visited"), 4.0) << summary["visits"].dump();
  for (const auto& [object, time_s] : summary.at("visits").items()) {
    EXPECT_TRUE(time_s.is_number()) << object << " was never visited";
  }
  const nlohmann::json& behaviour = summary.at("behaviour");
  EXPECT_EQ(behaviour.at("name"), "attention");
  EXPECT_EQ(behaviour.at("failed"), false);
  EXPECT_NE(behaviour.at("status").get<std::string>().find("saccades"), std::string::npos);
  for (const auto& loop : summary.at("loops")) {
    if (loop.at("name") == "behaviour") {
      EXPECT_TRUE(loop.at("allocation_exempt").get<bool>()) << loop.dump();
      EXPECT_GT(loop.at("cycles").get<long long>(), 0) << loop.dump();
    }
  }
}

TEST(BehaviourExperiments, AttentionScanVisitsEveryObjectOfItsScene) {
  expect_every_object_visited("attention_scan", "");
}

TEST(BehaviourExperiments, AttentionScanVisitsEveryObjectMovedElsewhereWithAnotherSeed) {
  // The objects mirrored left to right and shifted: nothing of the shipped layout is assumed.
  expect_every_object_visited("attention_scan_moved",
                              "--set experiment.seed=2 "
                              "--set 'scene.objects.0.xyz_m=[1.2, -0.25, 1.60]' "
                              "--set 'scene.objects.1.xyz_m=[1.4, 0.32, 1.50]' "
                              "--set 'scene.objects.2.xyz_m=[1.3, -0.2, 1.15]' "
                              "--set 'scene.objects.3.xyz_m=[1.3, 0.25, 1.22]' ");
}

TEST(BehaviourExperiments, APluginsBehaviourThatThrowsFailsTheRunWhichGoesOnHolding) {
  const fs::path folder = fs::temp_directory_path() / "cambio_behaviour_failing";
  fs::remove_all(folder);
  const fs::path experiment = write_experiment(folder, "    name: failing\n    plugins: ['" +
                                                           std::string(CAMBIO_TEST_PLUGIN) +
                                                           "']\n    params: {steps: 2}\n");
  const auto result = testing::run_cambio("run '" + experiment.string() + "' --out '" +
                                          (folder / "out").string() + "'");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("behaviour stopped: the behaviour's step() threw: the test "
                               "plugin's behaviour failed on purpose"),
            std::string::npos)
      << result.output;
  const nlohmann::json summary = read_summary(folder / "out");
  EXPECT_EQ(summary.at("outcome"), "behaviour_failed");
  EXPECT_EQ(summary.at("behaviour").at("failed"), true);
  EXPECT_EQ(summary.at("simulated_s"), 1.0);  // The run went on to its end.
  EXPECT_EQ(summary.at("gaze").at("final_action"), "hold");
}

TEST(BehaviourExperiments, AParameterTheBehaviourDoesNotHaveIsRefusedAtItsLine) {
  const fs::path folder = fs::temp_directory_path() / "cambio_behaviour_bad_param";
  fs::remove_all(folder);
  const fs::path experiment =
      write_experiment(folder, "    name: counting\n    plugins: ['" +
                                   std::string(CAMBIO_TEST_PLUGIN) + "']\n    params: {evry: 2}\n");
  const auto result = testing::run_cambio("run '" + experiment.string() + "'");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find(experiment.string() +
                               ":11: behaviour.params.evry: behaviour 'counting' has no parameter "
                               "of that name (did you mean 'every'?)"),
            std::string::npos)
      << result.output;
}

TEST(BehaviourExperiments, AnUnknownBehaviourIsOfferedTheRegisteredOnes) {
  const fs::path folder = fs::temp_directory_path() / "cambio_behaviour_unknown";
  fs::remove_all(folder);
  const fs::path experiment = write_experiment(folder, "    name: atention\n");
  const auto result = testing::run_cambio("run '" + experiment.string() + "'");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("no behaviour named 'atention' (did you mean 'attention'?); "
                               "registered: attention"),
            std::string::npos)
      << result.output;
}

}  // namespace
}  // namespace cambio
