#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <stdexcept>

#include "cambio/ros2/perception_link.hpp"
#include "dds_entities.hpp"
#include "link_messages.hpp"
#include "node_graph.hpp"

namespace cambio::ros2 {

// Deleting the participant deletes every entity it made.
struct RobotPerceptionLink::Dds {
  dds_entity_t participant = 0;
  std::array<dds_entity_t, 2> images{};
  std::array<std::string, 2> optical_frames;
  dds_entity_t request = 0;  // Writer.
  dds_entity_t results = 0;  // Reader.
  dds_entity_t waitset = 0;
  dds_entity_t stop_guard = 0;
  ~Dds() {
    if (participant > 0) dds_delete(participant);
  }
};

RobotPerceptionLink::RobotPerceptionLink(
    const RobotPerceptionLinkSettings& settings, std::function<std::int64_t()> now_ns,
    hal::TripleBuffer<hal::StereoFrame>& pairs, std::array<hal::CameraInfo, 2> cameras,
    const hal::SeqlockChannel<perception::SsmRequest>& requests,
    hal::SeqlockChannel<perception::SsmSummary>& results)
    : settings_(settings),
      now_ns_(std::move(now_ns)),
      pairs_(pairs),
      cameras_(std::move(cameras)),
      requests_(requests),
      results_(results) {
  if (!(settings_.link_timeout_s > 0.0) || !(settings_.max_result_age_s > 0.0)) {
    throw std::invalid_argument(
        "perception link: the link timeout and the results' age limit "
        "must be positive seconds");
  }
  dds_ = std::make_unique<Dds>();
  dds_->participant = dds::checked(dds_create_participant(settings_.domain_id, nullptr, nullptr),
                                   "join the DDS domain (check CYCLONEDDS_URI and the domain id)");
  const dds_entity_t participant = dds_->participant;
  // Reliable, as image_transport publishes by default: a fragment lost on the way is sent
  // again rather than losing the pair, and a best-effort (sensor-data) subscriber still matches.
  // Keep-last 2: the writer never waits; a pair the host has not acknowledged gives way to newer.
  const dds::Qos images(DDS_RELIABILITY_RELIABLE, 2);
  for (std::size_t eye = 0; eye < 2; ++eye) {
    dds_->optical_frames[eye] = cameras_[eye].name + "_optical_frame";
    dds_->images[eye] = dds::make_writer(participant, sensor_msgs_msg_dds__Image__desc,
                                         "/" + cameras_[eye].name + "/image_raw", images);
  }
  dds_->request =
      dds::make_writer(participant, cambio_msgs_msg_dds__SsmRequest__desc, kSsmRequestTopic,
                       dds::Qos(DDS_RELIABILITY_RELIABLE, 1, DDS_DURABILITY_TRANSIENT_LOCAL));
  dds_->results = dds::make_reader(participant, cambio_msgs_msg_dds__SsmSummary__desc,
                                   kSsmSummaryTopic, dds::Qos(DDS_RELIABILITY_RELIABLE, 10));
  const std::string what = "create the perception link's waitset";
  dds_->waitset = dds::checked(dds_create_waitset(participant), what);
  dds_->stop_guard = dds::checked(dds_create_guardcondition(participant), what);
  if (dds_waitset_attach(dds_->waitset,
                         dds::checked(dds_create_readcondition(dds_->results, DDS_ANY_STATE), what),
                         0) != DDS_RETCODE_OK ||
      dds_waitset_attach(dds_->waitset, dds_->stop_guard, 0) != DDS_RETCODE_OK) {
    throw std::runtime_error("ROS 2: cannot " + what);
  }
  bool announced = false;
  announce_node(participant, settings_.node_name, {dds_->images[0], dds_->images[1], dds_->request},
                {dds_->results}, announced);
  if (!announced) ++counts_.write_errors;
}

RobotPerceptionLink::~RobotPerceptionLink() {
  stop();
}

bool RobotPerceptionLink::wait_for_host(double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(timeout_s));
  for (;;) {
    dds_publication_matched_status_t left{};
    dds_publication_matched_status_t right{};
    dds_subscription_matched_status_t results{};
    if (dds_get_publication_matched_status(dds_->images[0], &left) == DDS_RETCODE_OK &&
        dds_get_publication_matched_status(dds_->images[1], &right) == DDS_RETCODE_OK &&
        dds_get_subscription_matched_status(dds_->results, &results) == DDS_RETCODE_OK &&
        left.current_count > 0 && right.current_count > 0 && results.current_count > 0) {
      return true;
    }
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

void RobotPerceptionLink::start() {
  if (!threads_.empty()) return;
  stopping_ = false;
  threads_.emplace_back([this] { send_pairs(); });
  threads_.emplace_back([this] { receive_results(); });
}

void RobotPerceptionLink::stop() {
  stopping_ = true;
  if (dds_ && dds_->stop_guard != 0) dds_set_guardcondition(dds_->stop_guard, true);
  for (std::thread& thread : threads_) thread.join();
  threads_.clear();
  // An outage still going when the run ends is reported as such (back_s < 0).
}

RobotPerceptionLinkCounts RobotPerceptionLink::counts() const {
  const std::lock_guard lock(mutex_);
  RobotPerceptionLinkCounts counts = counts_;
  counts.latency_median_ms = latencies_.percentile_us(0.5) / 1e3;
  counts.latency_max_ms = static_cast<double>(latencies_.max_ns()) / 1e6;
  return counts;
}

void RobotPerceptionLink::send_pairs() {
  std::uint64_t request_version = 0;
  perception::SsmRequest request;
  while (!stopping_) {
    if (pairs_.acquire()) {
      const hal::StereoFrame& pair = pairs_.front();
      if (origin_ns_.load() < 0) origin_ns_ = pair.left.stamp_ns;
      bool ok = true;
      for (std::size_t eye = 0; eye < 2; ++eye) {
        const hal::Image& image = eye == 0 ? pair.left : pair.right;
        const sensor_msgs_msg_dds__Image_ message =
            image_message(image, dds_->optical_frames[eye],
                          to_ros_time(image.stamp_ns, settings_.epoch_offset_ns));
        ok = dds_write(dds_->images[eye], &message) == DDS_RETCODE_OK && ok;
      }
      last_pair_sent_ns_ = now_ns_();
      const std::lock_guard lock(mutex_);
      ++(ok ? counts_.pairs_sent : counts_.write_errors);
    }
    const std::uint64_t version = requests_.version();
    if (version != request_version && requests_.read(request)) {
      request_version = version;
      const cambio_msgs_msg_dds__SsmRequest_ message =
          request_message(request, to_ros_time(now_ns_(), settings_.epoch_offset_ns));
      const bool ok = dds_write(dds_->request, &message) == DDS_RETCODE_OK;
      const std::lock_guard lock(mutex_);
      ++(ok ? counts_.requests_sent : counts_.write_errors);
    }
    // A camera pair every 1/30 s or so: polling every millisecond adds at most that to the trip.
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

void RobotPerceptionLink::receive_results() {
  constexpr int kBatch = 8;
  std::uint64_t used = 0;
  perception::SsmSummary summary;
  while (!stopping_) {
    // Woken by a result or by stop(); the timeout lets a silent link be noticed.
    dds_waitset_wait(dds_->waitset, nullptr, 0, DDS_MSECS(20));
    void* samples[kBatch] = {};
    dds_sample_info_t infos[kBatch];
    int n = 0;
    while ((n = dds_take(dds_->results, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto& message = *static_cast<const cambio_msgs_msg_dds__SsmSummary_*>(samples[i]);
        const std::string problem =
            summary_from_message(message, settings_.epoch_offset_ns, summary);
        const std::int64_t now_ns = now_ns_();
        const std::lock_guard lock(mutex_);
        ++counts_.results_received;
        if (!problem.empty()) {
          if (counts_.results_malformed++ == 0) {
            std::cerr << "cambio: perception link: a result refused: " << problem << "\n";
          }
          counts_.last_malformed = problem;
          continue;
        }
        const double age_s = static_cast<double>(now_ns - summary.stamp_ns) * 1e-9;
        if (age_s > settings_.max_result_age_s) {
          ++counts_.results_stale;
          continue;
        }
        // Numbered here: a host that restarts numbers from 1 again, and the gaze loop takes a
        // result as new by its number.
        summary.sequence = ++used;
        results_.write(summary);
        ++counts_.results_used;
        latencies_.record_ns(now_ns - summary.stamp_ns);
        last_result_ns_ = now_ns;
        if (lost_) {
          lost_ = false;
          LinkOutage& outage = counts_.outages.back();
          outage.back_s = static_cast<double>(now_ns - origin_ns_.load()) * 1e-9;
          std::cerr << "cambio: perception link back at " << outage.back_s << " s, after "
                    << outage.back_s - outage.lost_s << " s without results\n";
        }
      }
      dds_return_loan(dds_->results, samples, n);
    }
    note_result_gap(now_ns_());
  }
}

void RobotPerceptionLink::note_result_gap(std::int64_t now_ns) {
  const std::int64_t last_pair_ns = last_pair_sent_ns_.load();
  if (lost_ || last_pair_ns < 0) return;
  const auto timeout_ns = static_cast<std::int64_t>(settings_.link_timeout_s * 1e9);
  // Silent since the last result, or since the pairs began going out if none ever came.
  const std::int64_t since_ns = last_result_ns_ >= 0 ? last_result_ns_ : first_pair_ns_;
  if (first_pair_ns_ < 0) first_pair_ns_ = last_pair_ns;
  if (since_ns < 0 || now_ns - since_ns <= timeout_ns) return;
  lost_ = true;
  const std::lock_guard lock(mutex_);
  counts_.outages.push_back({static_cast<double>(now_ns - origin_ns_.load()) * 1e-9, -1.0});
  std::cerr << "cambio: perception link lost at " << counts_.outages.back().lost_s
            << " s: no result from the perception host for " << settings_.link_timeout_s
            << " s; the gaze holds its vergence until results come again\n";
}

}  // namespace cambio::ros2
