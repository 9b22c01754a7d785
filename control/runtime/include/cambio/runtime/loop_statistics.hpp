#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace cambio::runtime {

/// A fixed-size latency histogram: kBucketCount buckets (1 µs each by default: up to 10 ms), then
/// an overflow count. Recording is O(1), allocation-free and real-time safe, and its memory does
/// not grow with the samples (a node that runs for days keeps the same 40 KB); percentiles are
/// read at any time.
class LatencyHistogram {
 public:
  static constexpr int kBucketCount = 10'000;
  LatencyHistogram() noexcept = default;
  /// `bucket_ns` (> 0): each bucket's width; the range is kBucketCount of them.
  explicit LatencyHistogram(std::int64_t bucket_ns) noexcept
      : bucket_ns_(bucket_ns > 0 ? bucket_ns : 1000) {}

  void record_ns(std::int64_t latency_ns) noexcept;
  std::uint64_t count() const { return count_; }
  std::int64_t max_ns() const { return max_ns_; }
  std::int64_t min_ns() const { return count_ == 0 ? 0 : min_ns_; }
  double mean_ns() const { return count_ == 0 ? 0.0 : static_cast<double>(sum_ns_) / count_; }
  /// The sum of every recorded sample (negative samples count as 0).
  std::int64_t sum_ns() const { return sum_ns_; }
  /// The smallest latency (µs, bucket upper edge) below which `fraction` of samples fall;
  /// samples past the range report the maximum seen.
  double percentile_us(double fraction) const;

 private:
  std::int64_t bucket_ns_ = 1000;
  std::array<std::uint32_t, kBucketCount> buckets_{};
  std::uint64_t overflow_ = 0;
  std::uint64_t count_ = 0;
  std::int64_t sum_ns_ = 0;
  std::int64_t max_ns_ = 0;
  std::int64_t min_ns_ = INT64_MAX;
};

/// What one loop did over a run.
struct LoopStatistics {
  std::string name;
  double rate_hz = 0.0;
  std::uint64_t cycles = 0;
  std::uint64_t overruns = 0;        ///< Cycles whose update ended after the next deadline.
  std::uint64_t skipped_cycles = 0;  ///< Deadlines dropped by the skip overrun policy.
  std::uint64_t failed_updates = 0;  ///< update() returned something other than kOk/kNoNewData.
  std::uint64_t allocations = 0;     ///< Heap allocations made by update() calls.
  /// The loop declared that its update() allocates (hal::Loop::allocates_in_update): its
  /// allocations are reported but exempt from the zero-allocation gate.
  bool allocation_exempt = false;
  /// Latest-value reads that gave up on a writer caught mid-write (hal::SeqlockChannel::read),
  /// the loop keeping its last good value instead.
  std::uint64_t torn_reads = 0;
  /// The loop's last reported fault (hal::Loop::fault_message) and how many it reported.
  std::string fault_message;
  std::uint64_t faults = 0;
  LatencyHistogram wakeup_latency;  ///< now - deadline at the start of each update.
  LatencyHistogram execution_time;  ///< Duration of each update.
  bool realtime_priority_granted = false;
  bool cpu_affinity_granted = false;
};

/// True unless a loop that did not declare allocations allocated in update().
bool passes_allocation_gate(const LoopStatistics& stats);

/// How much of a run's wall time one loop spent in update(): the sum of its execution times.
struct WallTimeShare {
  std::string loop;
  double busy_s = 0.0;
  double share = 0.0;  ///< busy_s / the run's wall time.
};

/// Each loop's busy time as a share of `wall_s`, largest first, so a run names its bottleneck
/// without a profiler. On the lockstep executor the loops run one after another on one thread
/// and the shares plus "outside the loops" make 1; on the realtime executor they run on threads
/// of their own and may add up to more than 1 (one core is 1).
std::vector<WallTimeShare> wall_time_shares(const LoopStatistics* stats, std::size_t count,
                                            double wall_s);
/// The shares as lines, "camera  61.2 %  1.224 s", then what the loops leave of the wall time
/// when `sequential` (lockstep).
std::string format_wall_time_shares(const std::vector<WallTimeShare>& shares, double wall_s,
                                    bool sequential);
/// {"loops": {name: share, ...}, "outside_loops": share or null when not sequential, "wall_s"}.
nlohmann::ordered_json wall_time_shares_json(const std::vector<WallTimeShare>& shares,
                                             double wall_s, bool sequential);

/// Human-readable table of several loops' statistics.
std::string format_statistics_table(const LoopStatistics* stats, std::size_t count);
/// One JSON object for a loop: name, rate_hz, cycles, wake-up p50_us, p99_us, p999_us, max_us,
/// overruns, allocations (per cycle, total, exempt), torn_reads, faults, execution p50/p99/max.
nlohmann::ordered_json statistics_json(const LoopStatistics& stats);

}  // namespace cambio::runtime
