// `cambio can-bench --json`: the documented keys, positive figures, and the bus load counted from
// the traffic agreeing with the loader's closed-form model (a count, not a timing).
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "run_cambio.hpp"

namespace cambio {
namespace {

using testing::Capture;
using testing::run_cambio;

TEST(CanBench, JsonHasTheFiguresAndTheMeasuredLoadMatchesTheModel) {
  const auto result = run_cambio("can-bench --json --cycles 200", Capture::kStdout);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto figures = nlohmann::json::parse(result.output, nullptr, false);
  ASSERT_FALSE(figures.is_discarded()) << "not JSON:\n" << result.output;
  EXPECT_EQ(figures["bus"], "in-process (host)");
  EXPECT_EQ(figures["emulated"], false);
  EXPECT_GE(figures["rounds"].get<int>(), 10);
  EXPECT_EQ(figures["cycles_per_round"], 200);
  EXPECT_GT(figures["pdo_frames_per_s_per_core"].get<double>(), 0.0) << result.output;
  for (const char* drives : {"2", "5", "10"}) {
    const auto& cycle = figures["master_cycle_us"][drives];
    ASSERT_TRUE(cycle["p50"].is_number()) << drives << " drives in " << result.output;
    EXPECT_GT(cycle["p50"].get<double>(), 0.0) << drives;
    EXPECT_GE(cycle["p99"].get<double>(), cycle["p50"].get<double>()) << drives;
  }
  EXPECT_GT(figures["peak_rss_kib"].get<long>(), 0);

  // The pan-tilt at 1 kHz: per cycle 2 RPDO1, a SYNC and 2 TPDO1 on the bus, plus each drive's
  // heartbeat every 100 ms (at most 3 each in 0.2 s), and no SYNC left unanswered.
  EXPECT_EQ(figures["bus_load_rig"], "pan_tilt");
  EXPECT_EQ(figures["bus_load_rate_hz"], 1000.0);
  const auto frames = figures["bus_load_frames"].get<long>();
  EXPECT_GE(frames, 5 * 200);
  EXPECT_LE(frames, 5 * 200 + 2 * 3);
  EXPECT_EQ(figures["bus_load_missed_sync_answers"], 0);
  const double model = figures["bus_load_model"].get<double>();
  const double measured = figures["bus_load_measured"].get<double>();
  EXPECT_GT(model, 0.0);
  EXPECT_LE(model, 0.6) << "the shipped pan-tilt is within the loader's limit";
  EXPECT_LE(std::abs(measured - model), 0.1 * model) << result.output;
}

TEST(CanBench, RefusesTooFewCyclesOrRounds) {
  auto result = run_cambio("can-bench --cycles 10");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("'--cycles' expects a whole number in [100, 1000000]"),
            std::string::npos)
      << result.output;
  result = run_cambio("can-bench --rounds 3");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("'--rounds'"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace cambio
