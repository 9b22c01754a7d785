// End-to-end checks of the `cambio` program's contract: exit codes, messages, JSON keys.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "run_cambio.hpp"

namespace cambio {
namespace {

using testing::run_cambio;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The integer after `"key": ` in a JSON text (first occurrence), or -1.
long long json_integer(const std::string& text, const std::string& key) {
  const std::string pattern = "\"" + key + "\": ([0-9]+)";
  std::smatch match;
  if (!std::regex_search(text, match, std::regex(pattern))) return -1;
  return std::stoll(match[1].str());
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
  for (const char* key :
       {"\"loops\": [", "\"name\"", "\"rate_hz\": 2000", "\"p50_us\"", "\"p99_us\"", "\"p999_us\"",
        "\"max_us\"", "\"overruns\"", "\"allocations_per_cycle\": 0"}) {
    EXPECT_TRUE(contains(result.output, key)) << key << " missing from:\n" << result.output;
  }
  // 0.2 s at 2 kHz is 400 deadlines: each one either ran or was skipped after an overrun.
  EXPECT_EQ(json_integer(result.output, "cycles") + json_integer(result.output, "skipped_cycles"),
            400)
      << result.output;
}

TEST(CambioCli, LoopBenchRunsTheRigsLoops) {
  const auto result = run_cambio(
      "loop-bench --config firmware_config/rigs/cambio.yaml --set loops.joint.rate_hz=500 "
      "--duration-s 0.2 --json --no-lock-memory");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(contains(result.output, "\"name\": \"joint\", \"rate_hz\": 500, \"cycles\": "))
      << result.output;
  EXPECT_EQ(json_integer(result.output, "cycles") + json_integer(result.output, "skipped_cycles"),
            100)
      << result.output;
  EXPECT_TRUE(contains(result.output, "\"name\": \"camera\"")) << result.output;
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
  std::ifstream json(out_dir / "summary.json");
  const std::string text((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(contains(text, "\"allocations_per_cycle\": 0")) << text;
  EXPECT_FALSE(contains(text, "\"vergence\"")) << "task=hold runs no vergence loop: " << text;
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
  std::ifstream json(out_dir / "summary.json");
  const std::string text((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(contains(text, "\"vergence\": {")) << text;
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
