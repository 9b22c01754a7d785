// End-to-end checks of the `cambio` program's contract: exit codes, messages, JSON keys.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "run_cambio.hpp"

namespace cambio {
namespace {

using testing::run_cambio;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

nlohmann::json read_json(const std::filesystem::path& path) {
  std::ifstream file(path);
  return nlohmann::json::parse(file);  // Throws (failing the test) on a missing or invalid file.
}

TEST(CambioCli, HelpListsTheCommands) {
  const auto result = run_cambio("--help");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  for (const char* command : {"run", "check-config", "loop-bench"}) {
    EXPECT_TRUE(contains(result.output, command)) << command;
  }
}

TEST(CambioCli, UnknownCommandAndOptionAreBadInput) {
  auto result = run_cambio("frobnicate");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(result.output, "unknown command 'frobnicate'")) << result.output;
  result = run_cambio("loop-bench --rate 5");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(result.output, "unknown option '--rate'")) << result.output;
  result = run_cambio("loop-bench --rate-hz fast");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(result.output, "expects a number, got 'fast'")) << result.output;
}

TEST(CambioCli, EverySubcommandHasHelp) {
  for (const char* command : {"run", "check-config", "loop-bench"}) {
    const auto result = run_cambio(std::string(command) + " --help");
    EXPECT_EQ(result.exit_code, 0) << command << ": " << result.output;
    EXPECT_TRUE(contains(result.output, "usage: cambio " + std::string(command))) << result.output;
  }
}

TEST(CambioCli, LoopBenchJsonHasTheDocumentedKeys) {
  const auto result = run_cambio("loop-bench --rate-hz 2000 --duration-s 0.2 --json");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json report = nlohmann::json::parse(result.output);
  ASSERT_EQ(report.at("loops").size(), 1u) << result.output;
  const nlohmann::json& loop = report.at("loops")[0];
  EXPECT_EQ(loop.at("rate_hz"), 2000.0);
  for (const char* key :
       {"name", "p50_us", "p99_us", "p999_us", "max_us", "overruns", "torn_reads"}) {
    EXPECT_TRUE(loop.contains(key)) << key << " missing from:\n" << result.output;
  }
  EXPECT_EQ(loop.at("allocations_per_cycle"), 0.0);
  EXPECT_TRUE(report.at("warnings").is_array());
  // 0.2 s at 2 kHz is 400 deadlines: each one either ran or was skipped after an overrun.
  EXPECT_EQ(loop.at("cycles").get<long long>() + loop.at("skipped_cycles").get<long long>(), 400)
      << result.output;
}

TEST(CambioCli, LoopBenchRunsTheRigsLoops) {
  const auto result = run_cambio(
      "loop-bench --config firmware_config/rigs/cambio.yaml --set loops.joint.rate_hz=500 "
      "--duration-s 0.2 --json --no-lock-memory");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json report = nlohmann::json::parse(result.output);
  std::set<std::string> names;
  for (const auto& loop : report.at("loops")) {
    names.insert(loop.at("name").get<std::string>());
    if (loop.at("name") != "joint") continue;
    EXPECT_EQ(loop.at("rate_hz"), 500.0);
    EXPECT_EQ(loop.at("cycles").get<long long>() + loop.at("skipped_cycles").get<long long>(), 100)
        << result.output;
  }
  EXPECT_EQ(names, (std::set<std::string>{"joint", "control", "perception", "camera"}));
}

TEST(CambioCli, RunRefusesAMissingExperiment) {
  const auto result = run_cambio("run no/such/experiment.yaml");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "no/such/experiment.yaml")) << result.output;
}

TEST(CambioCli, RunRefusesABackendThatIsNotBuiltYet) {
  const auto result = run_cambio(
      "run firmware_config/experiments/sim_default.yaml --set rig.groups.head.backend=socketcan "
      "--set rig.loops.joint.rate_hz=500");  // 5 drives at 1 kHz would overload a 1 Mbit/s bus.
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "backend 'socketcan' requested by joint group 'head'"))
      << result.output;
  EXPECT_TRUE(contains(result.output, "not built yet")) << result.output;
}

TEST(CambioCli, RunTheSimDefaultBriefly) {
  const auto out_dir = std::filesystem::temp_directory_path() / "cambio_cli_test_run";
  std::filesystem::remove_all(out_dir);
  const auto result = run_cambio(
      "run firmware_config/experiments/sim_default.yaml --set experiment.duration_s=0.5 "
      "--set experiment.task=hold --out '" +
      out_dir.string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(contains(result.output, "joint")) << result.output;
  // 0.5 s at 30 Hz, two cameras: 15 frames each.
  EXPECT_TRUE(contains(result.output, "camera frames grabbed: 30")) << result.output;
  EXPECT_TRUE(std::filesystem::exists(out_dir / "left_eye.png"));
  EXPECT_TRUE(std::filesystem::exists(out_dir / "right_eye.png"));
  const nlohmann::json summary = read_json(out_dir / "summary.json");
  EXPECT_FALSE(summary.contains("vergence")) << "task=hold runs no vergence loop";
  EXPECT_EQ(summary.at("stereo_pairs"), 15);
  EXPECT_EQ(summary.at("mismatched_stereo_pairs"), 0);
  EXPECT_EQ(summary.at("joint_loop").at("fault_latched_at_end"), false);
}

// The main job end to end: the right eye starts 7 deg off and must verge on the textured sphere
// to within the experiment's goal of 1 px; the run exits 1 otherwise.
TEST(CambioCli, TheSimDefaultVergesOnTheTexturedSphere) {
  const auto out_dir = std::filesystem::temp_directory_path() / "cambio_cli_test_vergence";
  std::filesystem::remove_all(out_dir);
  const auto result = run_cambio("run firmware_config/experiments/sim_default.yaml --out '" +
                                 out_dir.string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(contains(result.output, "): verged")) << result.output;
  const nlohmann::json summary = read_json(out_dir / "summary.json");
  EXPECT_TRUE(summary.contains("vergence"));
  // The real loops of the main job (joint, vergence control, camera, SSM perception, physics)
  // make no heap allocation after configure(), and none declared that it must.
  std::set<std::string> loops;
  for (const auto& loop : summary.at("loops")) {
    loops.insert(loop.at("name").get<std::string>());
    EXPECT_GT(loop.at("cycles").get<long long>(), 0) << loop.dump();
    EXPECT_EQ(loop.at("allocations").get<long long>(), 0) << loop.dump();
    EXPECT_FALSE(loop.at("allocation_exempt").get<bool>()) << loop.dump();
    EXPECT_EQ(loop.at("faults").get<long long>(), 0) << loop.dump();
  }
  EXPECT_EQ(loops, (std::set<std::string>{"joint", "control", "camera", "perception", "physics"}));
  EXPECT_EQ(summary.at("allocation_gate").at("passed"), true);
  EXPECT_EQ(summary.at("mismatched_stereo_pairs"), 0);
}

TEST(CambioCli, RunReportsExperimentMistakesWithTheirLine) {
  const auto result = run_cambio(
      "run firmware_config/experiments/sim_default.yaml --set experiment.task=verge "
      "--set experiment.initial_pose.left_eye_pam_deg=3");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "experiment.task")) << result.output;
  EXPECT_TRUE(contains(result.output, "left_eye_pam_deg")) << result.output;
}

}  // namespace
}  // namespace cambio
