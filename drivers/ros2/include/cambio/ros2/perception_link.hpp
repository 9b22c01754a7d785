#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cambio/hal/camera.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/hal/stereo_frame.hpp"
#include "cambio/hal/triple_buffer.hpp"
#include "cambio/perception/ssm_server.hpp"
#include "cambio/runtime/loop_statistics.hpp"

namespace cambio::ros2 {

/// The topics the split between the robot and a perception host uses (ROS names; the stereo
/// pair's images go on /<camera>/image_raw, sensor_msgs/Image, ROS's sensor-data QoS:
/// best-effort keep-last 5, each eye stamped with its own exposure):
///   /cambio/perception/request  cambio_msgs/SsmRequest  reliable transient-local keep-last 1
///                               (robot -> host: where the retinas sit, which features)
///   /cambio/perception/summary  cambio_msgs/SsmSummary  reliable keep-last 10
///                               (host -> robot: one per stereo pair, stamped with the pair's
///                               left exposure, passed through from the image's header)
inline constexpr const char* kSsmRequestTopic = "/cambio/perception/request";
inline constexpr const char* kSsmSummaryTopic = "/cambio/perception/summary";

struct RobotPerceptionLinkSettings {
  std::uint32_t domain_id = 0;
  /// Run clock + offset = ROS time (0 on simulated time; CLOCK_REALTIME - CLOCK_MONOTONIC on a
  /// wall-clock run). Stamps go out as ROS time and come back the same way.
  std::int64_t epoch_offset_ns = 0;
  /// No result for this long while pairs go out: the link is lost (reported; the gaze holds its
  /// vergence, as it does without a new measurement) until one comes again.
  double link_timeout_s = 0.3;
  /// A result whose pair was exposed longer ago than this is stale and dropped (the gaze loop
  /// must not servo on what the eyes saw before a link outage).
  double max_result_age_s = 0.25;
  std::string node_name = "cambio_perception_link";
};

/// One outage: when no result had come for link_timeout_s, and when one came again, in seconds
/// since the first pair's exposure (the run's first camera cycle: its start, as a run's trace
/// counts time); back_s < 0 while it lasts.
struct LinkOutage {
  double lost_s = 0.0;
  double back_s = -1.0;
};

struct RobotPerceptionLinkCounts {
  std::uint64_t pairs_sent = 0;
  std::uint64_t requests_sent = 0;
  std::uint64_t results_received = 0;
  std::uint64_t results_used = 0;
  std::uint64_t results_stale = 0;      ///< Older than max_result_age_s on arrival.
  std::uint64_t results_malformed = 0;  ///< Refused by summary_from_message (last_malformed).
  std::uint64_t write_errors = 0;
  std::string last_malformed;
  /// Exposure to arrival of the results used (the pair's trip there, the SSM, the trip back):
  /// median and largest, ms.
  double latency_median_ms = 0.0;
  double latency_max_ms = 0.0;
  std::vector<LinkOutage> outages;
};

/// The robot's end of the split: the camera loop's stereo pairs go out to the perception host,
/// the gaze loop's SSM requests too, and the host's results come back into the same
/// latest-value channel an SsmServer on this machine would write: the gaze loop does not know
/// which it is. Threads of its own, not real-time: a loop never waits for the network.
class RobotPerceptionLink {
 public:
  /// `now_ns`: the run's clock. `pairs`: the camera loop's stereo channel (this link is its one
  /// reader). `requests` is read, `results` written (this link is its one writer). Throws
  /// std::runtime_error naming what Cyclone refused.
  RobotPerceptionLink(const RobotPerceptionLinkSettings& settings,
                      std::function<std::int64_t()> now_ns,
                      hal::TripleBuffer<hal::StereoFrame>& pairs,
                      std::array<hal::CameraInfo, 2> cameras,
                      const hal::SeqlockChannel<perception::SsmRequest>& requests,
                      hal::SeqlockChannel<perception::SsmSummary>& results);
  ~RobotPerceptionLink();
  RobotPerceptionLink(const RobotPerceptionLink&) = delete;
  RobotPerceptionLink& operator=(const RobotPerceptionLink&) = delete;

  /// Waits up to `timeout_s` (wall time) for a perception host to match: a reader of both
  /// images and a writer of results. False if none did.
  bool wait_for_host(double timeout_s);
  void start();
  void stop();
  RobotPerceptionLinkCounts counts() const;

 private:
  struct Dds;
  void send_pairs();
  void receive_results();
  void note_result_gap(std::int64_t now_ns);

  RobotPerceptionLinkSettings settings_;
  std::function<std::int64_t()> now_ns_;
  hal::TripleBuffer<hal::StereoFrame>& pairs_;
  std::array<hal::CameraInfo, 2> cameras_;
  const hal::SeqlockChannel<perception::SsmRequest>& requests_;
  hal::SeqlockChannel<perception::SsmSummary>& results_;
  std::unique_ptr<Dds> dds_;
  std::vector<std::thread> threads_;
  std::atomic<bool> stopping_{false};
  std::atomic<std::int64_t> last_pair_sent_ns_{-1};  // Run clock.
  mutable std::mutex mutex_;                         // Guards counts_ and latencies_.
  RobotPerceptionLinkCounts counts_;
  // Exposure to result, 0.1 ms buckets up to 1 s (older results are dropped as stale first).
  runtime::LatencyHistogram latencies_{100'000};
  // The receiving thread's (run clock): the last result used, the first pair it saw go out.
  std::int64_t last_result_ns_ = -1;
  std::int64_t first_pair_ns_ = -1;
  std::atomic<std::int64_t> origin_ns_{-1};  // Run clock: the first pair's exposure.
  bool lost_ = false;
};

struct PerceptionNodeSettings {
  std::uint32_t domain_id = 0;
  /// The robot's stereo pair (left, right) as its rig describes them: sizes, formats, rate.
  std::array<hal::CameraInfo, 2> cameras;
  std::string node_name = "cambio_perception";
};

struct PerceptionNodeCounts {
  std::uint64_t images_received = 0;
  std::uint64_t images_malformed = 0;
  std::uint64_t pairs_processed = 0;
  std::uint64_t pairs_rejected = 0;  ///< By the SSM (stamps too far apart, bad images).
  std::uint64_t requests_received = 0;
  std::uint64_t requests_malformed = 0;
  std::uint64_t results_sent = 0;
  std::uint64_t write_errors = 0;
  std::string last_problem;  ///< The last malformed image or request, named.
  double ssm_median_us = 0.0;
};

/// The perception host's end: the robot's stereo pairs in, paired by their stamps (within half
/// a camera period, as the SSM requires), through an SsmServer with the robot's SSM settings,
/// each result out with the pair's stamp; the robot's newest request applied to every pair.
class PerceptionNode {
 public:
  /// Throws std::invalid_argument for an SSM config that does not fit the cameras, and
  /// std::runtime_error naming what Cyclone refused.
  PerceptionNode(const PerceptionNodeSettings& settings, const perception::SsmConfig& ssm);
  ~PerceptionNode();
  PerceptionNode(const PerceptionNode&) = delete;
  PerceptionNode& operator=(const PerceptionNode&) = delete;

  /// Serves on this thread until `stop` is set or `duration_s` (> 0) of wall time has passed.
  void serve(const std::atomic<bool>& stop, double duration_s);
  PerceptionNodeCounts counts() const;

 private:
  struct Dds;
  void take_images(std::size_t eye);
  void take_requests();
  bool process_newest_pair();

  PerceptionNodeSettings settings_;
  std::unique_ptr<hal::TripleBuffer<hal::StereoFrame>> pairs_;
  std::unique_ptr<perception::SsmServer> server_;
  std::unique_ptr<Dds> dds_;
  // The two newest images of each eye ([eye][slot]), to pair by stamp.
  std::array<std::array<hal::Image, 2>, 2> recent_;
  std::array<std::size_t, 2> newest_slot_{};
  std::int64_t last_processed_stamp_ns_ = -1;
  std::int64_t max_skew_ns_ = 0;
  std::uint64_t cycle_ = 0;
  runtime::LatencyHistogram ssm_time_;  // The SSM's time per pair, 1 µs buckets up to 10 ms.
  mutable std::mutex mutex_;            // Guards counts_ and ssm_time_.
  PerceptionNodeCounts counts_;
};

}  // namespace cambio::ros2
