// End-to-end checks of the `cambio` program's contract: exit codes, messages, JSON keys.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "run_cambio.hpp"

namespace cambio {
namespace {

using testing::Capture;
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
  EXPECT_TRUE(contains(result.output, "'--rate-hz' expects a number in (0, 100000]"))
      << result.output;
  EXPECT_TRUE(contains(result.output, "got 'fast'")) << result.output;
}

TEST(CambioCli, EverySubcommandHasHelp) {
  for (const char* command : {"run", "check-config", "loop-bench"}) {
    const auto result = run_cambio(std::string(command) + " --help");
    EXPECT_EQ(result.exit_code, 0) << command << ": " << result.output;
    EXPECT_TRUE(contains(result.output, "usage: cambio " + std::string(command))) << result.output;
  }
}

// `text` as JSON; discarded (is_discarded()) when it is not valid JSON.
nlohmann::json parse_json(const std::string& text) {
  return nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
}

// The loop of a loop-bench report named `name`, or null.
nlohmann::json loop_named(const nlohmann::json& report, const std::string& name) {
  for (const auto& loop : report["loops"]) {
    if (loop["name"] == name) return loop;
  }
  return nullptr;
}

TEST(CambioCli, LoopBenchJsonHasTheDocumentedKeys) {
  const auto result =
      run_cambio("loop-bench --rate-hz 2000 --duration-s 0.2 --json", Capture::kStdout);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto report = parse_json(result.output);
  ASSERT_FALSE(report.is_discarded()) << "not JSON:\n" << result.output;
  EXPECT_TRUE(report["warnings"].is_array()) << result.output;
  ASSERT_EQ(report["loops"].size(), 1u) << result.output;
  const auto& loop = report["loops"][0];
  for (const char* key : {"name", "rate_hz", "p50_us", "p99_us", "p999_us", "max_us", "overruns",
                          "skipped_cycles", "torn_reads", "allocation_exempt"}) {
    EXPECT_TRUE(loop.contains(key)) << key << " missing from:\n" << result.output;
  }
  EXPECT_EQ(loop["rate_hz"], 2000) << result.output;
  EXPECT_EQ(loop["allocations_per_cycle"], 0) << result.output;
  // 0.2 s at 2 kHz is 400 deadlines: each one either ran or was skipped after an overrun.
  EXPECT_EQ(loop["cycles"].get<int>() + loop["skipped_cycles"].get<int>(), 400) << result.output;
}

TEST(CambioCli, LoopBenchRunsTheRigsLoops) {
  const auto result = run_cambio(
      "loop-bench --config firmware_config/rigs/cambio.yaml --set loops.joint.rate_hz=500 "
      "--duration-s 0.2 --json --no-lock-memory",
      Capture::kStdout);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto report = parse_json(result.output);
  ASSERT_FALSE(report.is_discarded()) << "not JSON:\n" << result.output;
  const auto joint = loop_named(report, "joint");
  ASSERT_TRUE(joint.is_object()) << result.output;
  EXPECT_EQ(joint["rate_hz"], 500) << result.output;
  EXPECT_EQ(joint["cycles"].get<int>() + joint["skipped_cycles"].get<int>(), 100) << result.output;
  EXPECT_TRUE(loop_named(report, "camera").is_object()) << result.output;
}

// A textured 320x240 grey pair, the right image the left shifted 3 px to the left.
void write_textured_pair(const std::filesystem::path& left, const std::filesystem::path& right) {
  cv::Mat texture(240, 320, CV_8U);
  cv::RNG rng(7);
  rng.fill(texture, cv::RNG::UNIFORM, 0, 256);
  cv::Mat shifted = texture.clone();
  texture(cv::Rect(3, 0, 317, 240)).copyTo(shifted(cv::Rect(0, 0, 317, 240)));
  ASSERT_TRUE(cv::imwrite(left.string(), texture));
  ASSERT_TRUE(cv::imwrite(right.string(), shifted));
}

// File names are user text: a quote or a backslash in one must still give valid JSON.
TEST(CambioCli, PerceiveWritesValidJsonWhateverTheFileNames) {
  const auto dir = std::filesystem::temp_directory_path() / "cambio_cli_test_perceive \"a\\b\"";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto left = dir / "left \"eye\".png";
  const auto right = dir / "right\\eye.png";
  write_textured_pair(left, right);
  const auto result = run_cambio("perceive --left '" + left.string() + "' --right '" +
                                 right.string() + "' --out '" + (dir / "out").string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::ifstream file(dir / "out" / "result.json");
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const auto json = parse_json(text);
  ASSERT_FALSE(json.is_discarded()) << "not JSON:\n" << text;
  EXPECT_EQ(json["left"], left.string());
  EXPECT_EQ(json["right"], right.string());
  EXPECT_EQ(json["image_size_px"], nlohmann::json::array({320, 240}));
  EXPECT_EQ(json["disparity_valid"].is_boolean() && json["disparity_valid"].get<bool>(),
            json["disparity_px"].is_number())
      << text;
  EXPECT_EQ(json["levels"].size(), json["retina"]["levels"].get<std::size_t>()) << text;
  EXPECT_FALSE(json["maps"].empty()) << text;
  EXPECT_TRUE(json["timings_us"].contains("total")) << text;
}

// The whole-range scan's hypotheses are reported (what a user tuning the SSM looks at when a
// periodic or striped texture is matched at the wrong disparity); without a scan, null.
TEST(CambioCli, PerceiveReportsTheScansCandidates) {
  const auto dir = std::filesystem::temp_directory_path() / "cambio_cli_test_perceive_scan";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_textured_pair(dir / "left.png", dir / "right.png");
  const std::string images = "perceive --left '" + (dir / "left.png").string() + "' --right '" +
                             (dir / "right.png").string() + "'";
  const auto read_result = [&](const std::string& out) {
    std::ifstream file(dir / out / "result.json");
    return parse_json(
        std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>()));
  };
  auto result = run_cambio(images + " --set disparity.scan_range_px=40 --out '" +
                           (dir / "scanned").string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto scanned = read_result("scanned");
  const auto& scan = scanned["scan"];
  ASSERT_TRUE(scan.is_object()) << scanned.dump();
  ASSERT_FALSE(scan["candidates"].empty()) << scan.dump();
  // The right image is the left moved 3 px to the left: x_left - x_right = +3 px.
  EXPECT_NEAR(scan["candidates"][0]["disparity_px"].get<double>(), 3.0, 1.0) << scan.dump();
  EXPECT_GT(scan["candidates"][0]["score"].get<double>(), 0.5) << scan.dump();
  EXPECT_GE(scan["window_tier"].get<int>(), 0) << scan.dump();

  result = run_cambio(images + " --set disparity.scan_range_px=0 --out '" +
                      (dir / "plain").string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(read_result("plain")["scan"].is_null());
}

TEST(CambioCli, PerceptionBenchPrintsTheFiguresAsJson) {
  const auto result = run_cambio("perception-bench --json --repeats 5", Capture::kStdout);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto figures = parse_json(result.output);
  ASSERT_FALSE(figures.is_discarded()) << "not JSON:\n" << result.output;
  EXPECT_EQ(figures["repeats"], 5);
  EXPECT_EQ(figures["true_disparity_px"], 3.3);
  // ssm_paper: the paper's retina (coarsest level covering the field) on grey frames;
  // ssm_paper_rgb the same on rgb8; ssm_fovea_only without the field-covering level.
  for (const char* key :
       {"ssm_paper_us", "ssm_paper_rgb_us", "ssm_fovea_only_us", "ssm_paper_over_memcpy",
        "ssm_64_us", "memcpy_us", "opencv_full_filter_us", "opencv_stereo_bm_us",
        "ssm_paper_lens_us", "ssm_paper_disparity_px"}) {
    EXPECT_TRUE(figures[key].is_number()) << key << " in " << result.output;
  }
  EXPECT_GE(figures["ssm_paper_over_memcpy_rounds"].get<int>(), 10) << result.output;
  for (const char* parts :
       {"ssm_paper_parts_us", "ssm_paper_rgb_parts_us", "ssm_fovea_only_parts_us"}) {
    EXPECT_TRUE(figures[parts].contains("retina")) << parts << " in " << result.output;
  }
  // The scan's cost is measured where it is cheapest (the textured pair: the fovea's window
  // decides) and where it is dearest (horizontal stripes: every window, up to the widest).
  EXPECT_EQ(figures["ssm_paper_scan_window_tier"], 0) << result.output;
  // The widest of DisparityScan's three windows.
  EXPECT_EQ(figures["ssm_paper_scan_widest_window_tier"], 2) << result.output;
  EXPECT_TRUE(figures["ssm_paper_scan_widest_window_over_ssm_paper"].is_number()) << result.output;
}

TEST(CambioCli, RunRefusesAMissingExperiment) {
  const auto result = run_cambio("run no/such/experiment.yaml");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "no/such/experiment.yaml")) << result.output;
}

// The head on socketcan with no drives to answer (this host has no kernel CAN; elsewhere the
// interface is absent or nothing answers on it): a device fault, exit 3, naming the bus.
TEST(CambioCli, RunOnCanWithoutItsBusIsADeviceFault) {
  const auto result = run_cambio(
      "run firmware_config/experiments/vergence_sphere.yaml --set "
      "rig.groups.head.backend=socketcan "
      "--set rig.can_buses.can0.interface=cambio_absent0");
  EXPECT_EQ(result.exit_code, 3) << result.output;
  EXPECT_TRUE(contains(result.output, "cambio_absent0")) << result.output;
}

// The same absent bus from the emulated drives' side: before, virtual-rig said exit 2 (bad input)
// where run and console said 3.
TEST(CambioCli, VirtualRigWithoutItsBusIsADeviceFaultAsForRun) {
  const auto result = run_cambio(
      "virtual-rig --config pan_tilt --duration-s 0.1 --set "
      "can_buses.can0.interface=cambio_absent0");
  EXPECT_EQ(result.exit_code, 3) << result.output;
  EXPECT_TRUE(contains(result.output, "cambio_absent0")) << result.output;
}

TEST(CambioCli, RunTheSimDefaultBriefly) {
  const auto out_dir = std::filesystem::temp_directory_path() / "cambio_cli_test_run";
  std::filesystem::remove_all(out_dir);
  const auto result =
      run_cambio("run tests/apps/data/sim_hold.yaml --out '" + out_dir.string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(contains(result.output, "joint")) << result.output;
  // 0.5 s at 30 Hz, two cameras: 15 frames each.
  EXPECT_TRUE(contains(result.output, "camera frames grabbed: 30")) << result.output;
  EXPECT_TRUE(std::filesystem::exists(out_dir / "left_eye.png"));
  EXPECT_TRUE(std::filesystem::exists(out_dir / "right_eye.png"));
  const nlohmann::json summary = read_json(out_dir / "summary.json");
  EXPECT_FALSE(summary.contains("gaze")) << "task=hold runs no gaze loop";
  EXPECT_EQ(summary.at("stereo_pairs"), 15);
  EXPECT_EQ(summary.at("mismatched_stereo_pairs"), 0);
  EXPECT_EQ(summary.at("joint_loop").at("fault_latched_at_end"), false);
  // The cameras' renderer, said on stderr and kept in the summary.
  EXPECT_TRUE(contains(result.output, "cambio run: renderer ")) << result.output;
  const auto& renderer = summary.at("renderer");
  for (const char* key : {"egl_platform", "gl_renderer", "gl_vendor"}) {
    EXPECT_TRUE(renderer.at(key).is_string()) << key << " in " << renderer.dump();
  }
  EXPECT_TRUE(renderer.at("egl_fallback_reason").is_string() ||
              renderer.at("egl_fallback_reason").is_null());
}

// The main job end to end: the right eye starts 7.8 deg off and must verge on the textured
// sphere; the run exits 1 unless the experiment's goals (settled within 1 s, |disparity| <= 0.5 px,
// true gaze error <= 0.1 deg) are met.
TEST(CambioCli, TheMainJobVergesOnTheTexturedSphere) {
  const auto out_dir = std::filesystem::temp_directory_path() / "cambio_cli_test_vergence";
  std::filesystem::remove_all(out_dir);
  const auto result = run_cambio("run firmware_config/experiments/vergence_sphere.yaml --out '" +
                                 out_dir.string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(contains(result.output, "goal true_gaze_error_deg <= 0.1: ")) << result.output;
  const nlohmann::json summary = read_json(out_dir / "summary.json");
  EXPECT_EQ(summary.at("passed"), true);
  EXPECT_LE(std::abs(summary.at("metrics").at("final_disparity_px").get<double>()), 0.5);
  EXPECT_GT(summary.at("gaze").at("vergence_corrections").get<int>(), 0);
  // The real loops of the main job make no heap allocation after configure() (malloc counted as
  // well as operator new), the gaze and arm loops' control laws included; only the loops that
  // are no control loops say they may: the evaluation's trace (ground truth, key frames) and the
  // camera loop grabbing the sim's cameras (Mesa's renderer allocates).
  std::set<std::string> loops;
  for (const auto& loop : summary.at("loops")) {
    const std::string name = loop.at("name");
    loops.insert(name);
    EXPECT_GT(loop.at("cycles").get<long long>(), 0) << loop.dump();
    EXPECT_EQ(loop.at("faults").get<long long>(), 0) << loop.dump();
    const bool declared = name == "trace" || name == "camera";
    EXPECT_EQ(loop.at("allocation_exempt").get<bool>(), declared) << loop.dump();
    if (!declared) {
      EXPECT_EQ(loop.at("allocations").get<long long>(), 0) << loop.dump();
    }
  }
  // rigs/cambio.yaml runs the head at loops.joint.rate_hz and both arms at 250 Hz of their own;
  // its arms carry touch sensors, so a gaze run has the arm loop too.
  EXPECT_EQ(loops, (std::set<std::string>{"joint", "joint.left_arm+right_arm", "script", "arm",
                                          "control", "trace", "camera", "perception", "physics"}));
  EXPECT_EQ(summary.at("allocation_gate").at("passed"), true);
  EXPECT_EQ(summary.at("mismatched_stereo_pairs"), 0);
  // The share of wall time each loop took: every loop named, the lockstep shares and what the
  // loops leave adding up to the whole run.
  const auto& shares = summary.at("wall_time_shares");
  double total = shares.at("outside_loops").get<double>();
  for (const auto& name : loops) total += shares.at("loops").at(name).get<double>();
  EXPECT_NEAR(total, 1.0, 1e-6) << shares.dump();
  EXPECT_TRUE(contains(result.output, "wall time ")) << result.output;
}

// A goal the run cannot meet: the run completes, says which goal failed, and exits 1.
TEST(CambioCli, AMissedGoalExitsOne) {
  const auto out_dir = std::filesystem::temp_directory_path() / "cambio_cli_test_missed_goal";
  std::filesystem::remove_all(out_dir);
  const auto result = run_cambio(
      "run firmware_config/experiments/vergence_sphere.yaml --set experiment.duration_s=1.0 "
      "--set experiment.goals.settle_time_s.max=0.01 --out '" +
      out_dir.string() + "'");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_TRUE(contains(result.output, "goal settle_time_s <= 0.01: ")) << result.output;
  const nlohmann::json summary = read_json(out_dir / "summary.json");
  EXPECT_EQ(summary.at("passed"), false);
  EXPECT_EQ(summary.at("outcome"), "goal_failed");
  EXPECT_EQ(summary.at("goals").at("settle_time_s").at("passed"), false);
  EXPECT_EQ(summary.at("goals").at("true_gaze_error_deg").at("passed"), true);
}

TEST(CambioCli, RunReportsExperimentMistakesWithTheirLine) {
  const auto result = run_cambio(
      "run firmware_config/experiments/vergence_sphere.yaml --set experiment.task=verge "
      "--set experiment.initial_pose.left_eye_pam_deg=3");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "experiment.task")) << result.output;
  EXPECT_TRUE(contains(result.output, "left_eye_pam_deg")) << result.output;
}

}  // namespace
}  // namespace cambio
