#include "cambio/runtime/loop_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cambio::runtime {

void LatencyHistogram::record_ns(std::int64_t latency_ns) noexcept {
  if (latency_ns < 0) latency_ns = 0;  // A wake-up can only be late; clamp clock noise.
  const std::int64_t bucket = latency_ns / 1000;
  if (bucket < kBucketCount) {
    ++buckets_[static_cast<std::size_t>(bucket)];
  } else {
    ++overflow_;
  }
  ++count_;
  sum_ns_ += latency_ns;
  max_ns_ = std::max(max_ns_, latency_ns);
  min_ns_ = std::min(min_ns_, latency_ns);
}

double LatencyHistogram::percentile_us(double fraction) const {
  if (count_ == 0) return 0.0;
  const auto rank = static_cast<std::uint64_t>(std::ceil(fraction * static_cast<double>(count_)));
  std::uint64_t seen = 0;
  for (int i = 0; i < kBucketCount; ++i) {
    seen += buckets_[static_cast<std::size_t>(i)];
    if (seen >= std::max<std::uint64_t>(rank, 1)) {
      // The bucket's upper edge, but never more than the true maximum.
      return std::min(static_cast<double>(i + 1), static_cast<double>(max_ns_) / 1000.0);
    }
  }
  return static_cast<double>(max_ns_) / 1000.0;
}

namespace {
double per_cycle(std::uint64_t total, std::uint64_t cycles) {
  return cycles == 0 ? 0.0 : static_cast<double>(total) / static_cast<double>(cycles);
}
}  // namespace

std::string format_statistics_table(const LoopStatistics* stats, std::size_t count) {
  std::string out;
  char line[256];
  std::snprintf(line, sizeof line, "%-12s %8s %9s %9s %9s %9s %9s %8s %9s %10s\n", "loop",
                "rate_hz", "cycles", "p50_us", "p99_us", "p99.9_us", "max_us", "overruns",
                "exec_p99", "alloc/cyc");
  out += line;
  for (std::size_t i = 0; i < count; ++i) {
    const LoopStatistics& s = stats[i];
    std::snprintf(line, sizeof line,
                  "%-12s %8.1f %9llu %9.1f %9.1f %9.1f %9.1f %8llu %9.1f %10.3f\n", s.name.c_str(),
                  s.rate_hz, static_cast<unsigned long long>(s.cycles),
                  s.wakeup_latency.percentile_us(0.50), s.wakeup_latency.percentile_us(0.99),
                  s.wakeup_latency.percentile_us(0.999),
                  static_cast<double>(s.wakeup_latency.max_ns()) / 1000.0,
                  static_cast<unsigned long long>(s.overruns), s.execution_time.percentile_us(0.99),
                  per_cycle(s.allocations, s.cycles));
    out += line;
  }
  return out;
}

std::string statistics_json(const LoopStatistics& s) {
  char text[768];
  std::snprintf(
      text, sizeof text,
      "{\"name\": \"%s\", \"rate_hz\": %.6g, \"cycles\": %llu, \"p50_us\": %.3f, \"p99_us\": %.3f, "
      "\"p999_us\": %.3f, \"max_us\": %.3f, \"mean_us\": %.3f, \"overruns\": %llu, "
      "\"skipped_cycles\": %llu, \"failed_updates\": %llu, \"allocations_per_cycle\": %.6g, "
      "\"exec_p50_us\": %.3f, \"exec_p99_us\": %.3f, \"exec_max_us\": %.3f, "
      "\"realtime_priority\": %s, \"cpu_affinity\": %s}",
      s.name.c_str(), s.rate_hz, static_cast<unsigned long long>(s.cycles),
      s.wakeup_latency.percentile_us(0.50), s.wakeup_latency.percentile_us(0.99),
      s.wakeup_latency.percentile_us(0.999),
      static_cast<double>(s.wakeup_latency.max_ns()) / 1000.0, s.wakeup_latency.mean_ns() / 1000.0,
      static_cast<unsigned long long>(s.overruns),
      static_cast<unsigned long long>(s.skipped_cycles),
      static_cast<unsigned long long>(s.failed_updates), per_cycle(s.allocations, s.cycles),
      s.execution_time.percentile_us(0.50), s.execution_time.percentile_us(0.99),
      static_cast<double>(s.execution_time.max_ns()) / 1000.0,
      s.realtime_priority_granted ? "true" : "false", s.cpu_affinity_granted ? "true" : "false");
  return text;
}

}  // namespace cambio::runtime
