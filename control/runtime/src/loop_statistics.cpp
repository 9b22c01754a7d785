#include "cambio/runtime/loop_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cambio::runtime {

void LatencyHistogram::record_ns(std::int64_t latency_ns) noexcept {
  if (latency_ns < 0) latency_ns = 0;  // A wake-up can only be late; clamp clock noise.
  const std::int64_t bucket = latency_ns / bucket_ns_;
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
      return std::min(static_cast<double>((i + 1) * bucket_ns_) / 1000.0,
                      static_cast<double>(max_ns_) / 1000.0);
    }
  }
  return static_cast<double>(max_ns_) / 1000.0;
}

namespace {
double per_cycle(std::uint64_t total, std::uint64_t cycles) {
  return cycles == 0 ? 0.0 : static_cast<double>(total) / static_cast<double>(cycles);
}
}  // namespace

bool passes_allocation_gate(const LoopStatistics& stats) {
  return stats.allocation_exempt || stats.allocations == 0;
}

std::string format_statistics_table(const LoopStatistics* stats, std::size_t count) {
  std::string out;
  char line[320];
  // The name column fits the longest name ("joint.left_arm+right_arm"), at least 12 wide.
  int name_width = 12;
  for (std::size_t i = 0; i < count; ++i) {
    name_width =
        std::max(name_width, static_cast<int>(std::min<std::size_t>(stats[i].name.size(), 64)));
  }
  std::snprintf(line, sizeof line, "%-*s %8s %9s %9s %9s %9s %9s %8s %9s %10s %6s\n", name_width,
                "loop", "rate_hz", "cycles", "p50_us", "p99_us", "p99.9_us", "max_us", "overruns",
                "exec_p99", "alloc/cyc", "torn");
  out += line;
  for (std::size_t i = 0; i < count; ++i) {
    const LoopStatistics& s = stats[i];
    std::snprintf(line, sizeof line,
                  "%-*.*s %8.1f %9llu %9.1f %9.1f %9.1f %9.1f %8llu %9.1f %10.3f%s %5llu\n",
                  name_width, name_width, s.name.c_str(), s.rate_hz,
                  static_cast<unsigned long long>(s.cycles), s.wakeup_latency.percentile_us(0.50),
                  s.wakeup_latency.percentile_us(0.99), s.wakeup_latency.percentile_us(0.999),
                  static_cast<double>(s.wakeup_latency.max_ns()) / 1000.0,
                  static_cast<unsigned long long>(s.overruns), s.execution_time.percentile_us(0.99),
                  per_cycle(s.allocations, s.cycles), s.allocation_exempt ? "*" : " ",
                  static_cast<unsigned long long>(s.torn_reads));
    out += line;
  }
  bool any_exempt = false;
  for (std::size_t i = 0; i < count; ++i) any_exempt = any_exempt || stats[i].allocation_exempt;
  if (any_exempt)
    out += "* declared to allocate in update() (exempt from the zero-allocation gate)\n";
  for (std::size_t i = 0; i < count; ++i) {
    if (stats[i].faults == 0) continue;
    out += "loop '" + stats[i].name + "' reported " + std::to_string(stats[i].faults) +
           " fault(s), the last: " + stats[i].fault_message + "\n";
  }
  return out;
}

std::vector<WallTimeShare> wall_time_shares(const LoopStatistics* stats, std::size_t count,
                                            double wall_s) {
  std::vector<WallTimeShare> shares;
  shares.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double busy_s = static_cast<double>(stats[i].execution_time.sum_ns()) * 1e-9;
    shares.push_back({stats[i].name, busy_s, wall_s > 0.0 ? busy_s / wall_s : 0.0});
  }
  std::stable_sort(
      shares.begin(), shares.end(),
      [](const WallTimeShare& a, const WallTimeShare& b) { return a.busy_s > b.busy_s; });
  return shares;
}

namespace {
double busy_sum_s(const std::vector<WallTimeShare>& shares) {
  double sum = 0.0;
  for (const auto& share : shares) sum += share.busy_s;
  return sum;
}
}  // namespace

std::string format_wall_time_shares(const std::vector<WallTimeShare>& shares, double wall_s,
                                    bool sequential) {
  std::string out;
  char line[160];
  std::snprintf(line, sizeof line, "wall time %.3f s, %s:\n", wall_s,
                sequential ? "the loops one after another (lockstep)"
                           : "each loop on its own thread (shares of one core)");
  out += line;
  int name_width = 12;
  for (const auto& share : shares) {
    name_width =
        std::max(name_width, static_cast<int>(std::min<std::size_t>(share.loop.size(), 64)));
  }
  for (const auto& share : shares) {
    std::snprintf(line, sizeof line, "  %-*.*s %6.1f %%  %8.3f s\n", name_width, name_width,
                  share.loop.c_str(), 100.0 * share.share, share.busy_s);
    out += line;
  }
  if (sequential && wall_s > 0.0) {
    const double outside_s = std::max(0.0, wall_s - busy_sum_s(shares));
    std::snprintf(line, sizeof line, "  %-*s %6.1f %%  %8.3f s\n", name_width, "outside loops",
                  100.0 * outside_s / wall_s, outside_s);
    out += line;
  }
  return out;
}

nlohmann::ordered_json wall_time_shares_json(const std::vector<WallTimeShare>& shares,
                                             double wall_s, bool sequential) {
  nlohmann::ordered_json json;
  json["wall_s"] = wall_s;
  json["loops"] = nlohmann::ordered_json::object();
  for (const auto& share : shares) json["loops"][share.loop] = share.share;
  json["outside_loops"] =
      sequential && wall_s > 0.0
          ? nlohmann::ordered_json(std::max(0.0, wall_s - busy_sum_s(shares)) / wall_s)
          : nlohmann::ordered_json(nullptr);
  return json;
}

nlohmann::ordered_json statistics_json(const LoopStatistics& s) {
  nlohmann::ordered_json json;
  json["name"] = s.name;
  json["rate_hz"] = s.rate_hz;
  json["cycles"] = s.cycles;
  json["p50_us"] = s.wakeup_latency.percentile_us(0.50);
  json["p99_us"] = s.wakeup_latency.percentile_us(0.99);
  json["p999_us"] = s.wakeup_latency.percentile_us(0.999);
  json["max_us"] = static_cast<double>(s.wakeup_latency.max_ns()) / 1000.0;
  json["mean_us"] = s.wakeup_latency.mean_ns() / 1000.0;
  json["overruns"] = s.overruns;
  json["skipped_cycles"] = s.skipped_cycles;
  json["failed_updates"] = s.failed_updates;
  json["allocations_per_cycle"] = per_cycle(s.allocations, s.cycles);
  json["allocations"] = s.allocations;
  json["allocation_exempt"] = s.allocation_exempt;
  json["torn_reads"] = s.torn_reads;
  json["faults"] = s.faults;
  json["fault_message"] = s.fault_message;
  json["exec_p50_us"] = s.execution_time.percentile_us(0.50);
  json["exec_p99_us"] = s.execution_time.percentile_us(0.99);
  json["exec_max_us"] = static_cast<double>(s.execution_time.max_ns()) / 1000.0;
  json["realtime_priority"] = s.realtime_priority_granted;
  json["cpu_affinity"] = s.cpu_affinity_granted;
  return json;
}

}  // namespace cambio::runtime
