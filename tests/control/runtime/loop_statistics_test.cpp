#include "cambio/runtime/loop_statistics.hpp"

#include <initializer_list>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace cambio::runtime {
namespace {

TEST(LatencyHistogram, PercentilesOfAKnownDistribution) {
  LatencyHistogram histogram;
  // 1000 samples: 1 µs .. 1000 µs, each once (recorded 0.5 µs into its bucket).
  for (int us = 1; us <= 1000; ++us) histogram.record_ns(us * 1000 - 500);
  EXPECT_EQ(histogram.count(), 1000u);
  EXPECT_DOUBLE_EQ(histogram.percentile_us(0.50), 500.0);
  EXPECT_DOUBLE_EQ(histogram.percentile_us(0.99), 990.0);
  EXPECT_DOUBLE_EQ(histogram.percentile_us(0.999), 999.0);
  EXPECT_EQ(histogram.max_ns(), 999'500);
}

TEST(LatencyHistogram, SamplesBeyondTheRangeReportTheTrueMaximum) {
  LatencyHistogram histogram;
  histogram.record_ns(3'000);
  histogram.record_ns(50'000'000);  // 50 ms
  EXPECT_DOUBLE_EQ(histogram.percentile_us(1.0), 50'000.0);
  EXPECT_DOUBLE_EQ(histogram.percentile_us(0.5), 4.0);
}

TEST(LatencyHistogram, WiderBucketsCoverMillisecondsInTheSameMemory) {
  // The perception link's: 0.1 ms buckets, so network latencies of tens of ms have a median
  // without keeping every sample.
  LatencyHistogram histogram(100'000);
  // 0.05 ms into each 0.1 ms bucket from 10.0 to 59.9 ms: 500 samples, the middle one 34.95 ms.
  for (int tenth = 100; tenth < 600; ++tenth) histogram.record_ns(tenth * 100'000 + 50'000);
  EXPECT_DOUBLE_EQ(histogram.percentile_us(0.5), 35'000.0);
  EXPECT_DOUBLE_EQ(histogram.percentile_us(1.0), 59'950.0);
  EXPECT_EQ(sizeof(histogram), sizeof(LatencyHistogram));
  histogram.record_ns(2'000'000'000);  // 2 s: past the range
  EXPECT_DOUBLE_EQ(histogram.percentile_us(1.0), 2'000'000.0);
}

TEST(LoopStatistics, JsonCarriesTheKeysLoopBenchPromises) {
  LoopStatistics stats;
  stats.name = "joint";
  stats.rate_hz = 1000;
  stats.cycles = 10;
  const nlohmann::json json = statistics_json(stats);
  EXPECT_EQ(json.at("name"), "joint");
  EXPECT_EQ(json.at("rate_hz"), 1000.0);
  EXPECT_EQ(json.at("cycles"), 10u);
  for (const char* key : {"p50_us", "p99_us", "p999_us", "max_us", "overruns",
                          "allocations_per_cycle", "allocation_exempt", "torn_reads", "faults"}) {
    EXPECT_TRUE(json.contains(key)) << key << " missing from " << json.dump();
  }
}

TEST(LoopStatistics, JsonStaysValidWhateverTheNamesAndMessages) {
  LoopStatistics stats;
  stats.name = "a \"quoted\" loop\\";
  stats.fault_message = "line one\nline \"two\"";
  const nlohmann::json parsed = nlohmann::json::parse(statistics_json(stats).dump());
  EXPECT_EQ(parsed.at("name"), stats.name);
  EXPECT_EQ(parsed.at("fault_message"), stats.fault_message);
}

LoopStatistics busy_loop(const std::string& name, std::initializer_list<std::int64_t> updates_ns) {
  LoopStatistics stats;
  stats.name = name;
  for (const std::int64_t ns : updates_ns) stats.execution_time.record_ns(ns);
  stats.cycles = updates_ns.size();
  return stats;
}

TEST(WallTimeShares, EachLoopsBusyTimeOverTheWallTimeLargestFirst) {
  const std::vector<LoopStatistics> loops = {busy_loop("control", {100'000'000, 100'000'000}),
                                             busy_loop("camera", {500'000'000}),
                                             busy_loop("idle", {})};
  const auto shares = wall_time_shares(loops.data(), loops.size(), 1.0);
  ASSERT_EQ(shares.size(), 3U);
  EXPECT_EQ(shares[0].loop, "camera");
  EXPECT_DOUBLE_EQ(shares[0].busy_s, 0.5);
  EXPECT_DOUBLE_EQ(shares[0].share, 0.5);
  EXPECT_EQ(shares[1].loop, "control");
  EXPECT_DOUBLE_EQ(shares[1].share, 0.2);
  EXPECT_EQ(shares[2].loop, "idle");
  EXPECT_DOUBLE_EQ(shares[2].share, 0.0);
  // Lockstep: what the loops leave is reported; realtime: loops overlap, so it is not.
  const nlohmann::json lockstep = wall_time_shares_json(shares, 1.0, true);
  EXPECT_NEAR(lockstep.at("outside_loops").get<double>(), 0.3, 1e-12);
  EXPECT_DOUBLE_EQ(lockstep.at("loops").at("camera").get<double>(), 0.5);
  EXPECT_TRUE(wall_time_shares_json(shares, 1.0, false).at("outside_loops").is_null());
  const std::string text = format_wall_time_shares(shares, 1.0, true);
  EXPECT_NE(text.find("camera"), std::string::npos) << text;
  EXPECT_NE(text.find("50.0 %"), std::string::npos) << text;
  EXPECT_NE(text.find("outside loops"), std::string::npos) << text;
}

TEST(WallTimeShares, AZeroWallTimeGivesZeroSharesNotInfinities) {
  const std::vector<LoopStatistics> loops = {busy_loop("camera", {1'000})};
  const auto shares = wall_time_shares(loops.data(), loops.size(), 0.0);
  EXPECT_EQ(shares[0].share, 0.0);
  EXPECT_TRUE(wall_time_shares_json(shares, 0.0, true).at("outside_loops").is_null());
}

}  // namespace
}  // namespace cambio::runtime
