#include "cambio/runtime/loop_statistics.hpp"

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

}  // namespace
}  // namespace cambio::runtime
