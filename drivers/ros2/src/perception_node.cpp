#include <algorithm>
#include <chrono>
#include <iostream>
#include <stdexcept>

#include "cambio/ros2/perception_link.hpp"
#include "dds_entities.hpp"
#include "link_messages.hpp"
#include "node_graph.hpp"

namespace cambio::ros2 {

// Deleting the participant deletes every entity it made.
struct PerceptionNode::Dds {
  dds_entity_t participant = 0;
  std::array<dds_entity_t, 2> images{};  // Readers.
  dds_entity_t request = 0;              // Reader.
  dds_entity_t results = 0;              // Writer.
  dds_entity_t waitset = 0;
  std::unique_ptr<SsmSummaryMessage> result;
  ~Dds() {
    if (participant > 0) dds_delete(participant);
  }
};

PerceptionNode::PerceptionNode(const PerceptionNodeSettings& settings,
                               const perception::SsmConfig& ssm)
    : settings_(settings) {
  const auto& [left, right] = settings_.cameras;
  for (std::size_t eye = 0; eye < 2; ++eye) {
    const hal::CameraIntrinsics& in = settings_.cameras[eye].intrinsics;
    for (hal::Image& image : recent_[eye]) {
      image.resize(in.width_px, in.height_px, settings_.cameras[eye].format);
    }
  }
  // Every slot of the pair channel sized once: writing a pair into it never allocates.
  pairs_ = std::make_unique<hal::TripleBuffer<hal::StereoFrame>>(
      hal::StereoFrame{recent_[0][0], recent_[1][0]});
  server_ = std::make_unique<perception::SsmServer>("perception", *pairs_, left, right, ssm);
  server_->configure();  // Throws for a config that does not fit the cameras.
  server_->activate();
  max_skew_ns_ = server_->max_stamp_skew_ns();

  dds_ = std::make_unique<Dds>();
  dds_->participant = dds::checked(dds_create_participant(settings_.domain_id, nullptr, nullptr),
                                   "join the DDS domain (check CYCLONEDDS_URI and the domain id)");
  const dds_entity_t participant = dds_->participant;
  const dds::Qos images(DDS_RELIABILITY_RELIABLE, 2);  // As the robot's link writes them.
  const std::string what = "create the perception node's waitset";
  dds_->waitset = dds::checked(dds_create_waitset(participant), what);
  for (std::size_t eye = 0; eye < 2; ++eye) {
    dds_->images[eye] = dds::make_reader(participant, sensor_msgs_msg_dds__Image__desc,
                                         "/" + settings_.cameras[eye].name + "/image_raw", images);
  }
  dds_->request =
      dds::make_reader(participant, cambio_msgs_msg_dds__SsmRequest__desc, kSsmRequestTopic,
                       dds::Qos(DDS_RELIABILITY_RELIABLE, 1, DDS_DURABILITY_TRANSIENT_LOCAL));
  dds_->results = dds::make_writer(participant, cambio_msgs_msg_dds__SsmSummary__desc,
                                   kSsmSummaryTopic, dds::Qos(DDS_RELIABILITY_RELIABLE, 10));
  for (const dds_entity_t reader : {dds_->images[0], dds_->images[1], dds_->request}) {
    if (dds_waitset_attach(dds_->waitset,
                           dds::checked(dds_create_readcondition(reader, DDS_ANY_STATE), what),
                           0) != DDS_RETCODE_OK) {
      throw std::runtime_error("ROS 2: cannot " + what);
    }
  }
  dds_->result = std::make_unique<SsmSummaryMessage>(left.name + "_optical_frame");
  bool announced = false;
  announce_node(participant, settings_.node_name, {dds_->results},
                {dds_->images[0], dds_->images[1], dds_->request}, announced);
  if (!announced) ++counts_.write_errors;
}

PerceptionNode::~PerceptionNode() = default;

PerceptionNodeCounts PerceptionNode::counts() const {
  const std::lock_guard lock(mutex_);
  PerceptionNodeCounts counts = counts_;
  if (ssm_time_.count() > 0) counts.ssm_median_us = ssm_time_.percentile_us(0.5);
  return counts;
}

void PerceptionNode::serve(const std::atomic<bool>& stop, double duration_s) {
  const auto start = std::chrono::steady_clock::now();
  while (!stop.load()) {
    if (duration_s > 0.0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >=
            duration_s) {
      return;
    }
    // The timeout bounds how late a stop is seen.
    dds_waitset_wait(dds_->waitset, nullptr, 0, DDS_MSECS(50));
    take_requests();
    take_images(0);
    take_images(1);
    process_newest_pair();
  }
}

void PerceptionNode::take_requests() {
  void* samples[1] = {};
  dds_sample_info_t infos[1];
  while (dds_take(dds_->request, samples, infos, 1, 1) > 0) {
    if (infos[0].valid_data) {
      perception::SsmRequest request;
      const std::string problem =
          request_from_message(*static_cast<const cambio_msgs_msg_dds__SsmRequest_*>(samples[0]),
                               settings_.cameras[0].intrinsics, request);
      const std::lock_guard lock(mutex_);
      ++counts_.requests_received;
      if (problem.empty()) {
        server_->requests().write(request);
      } else {
        ++counts_.requests_malformed;
        counts_.last_problem = std::string(kSsmRequestTopic) + ": " + problem;
        std::cerr << "cambio node perception: refused " << counts_.last_problem << "\n";
      }
    }
    dds_return_loan(dds_->request, samples, 1);
  }
}

void PerceptionNode::take_images(std::size_t eye) {
  constexpr int kBatch = 4;
  void* samples[kBatch] = {};
  dds_sample_info_t infos[kBatch];
  int n = 0;
  while ((n = dds_take(dds_->images[eye], samples, infos, kBatch, kBatch)) > 0) {
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      // Into the older slot: the newest stays for a partner that has not arrived yet.
      const std::size_t slot = 1 - newest_slot_[eye];
      hal::Image& image = recent_[eye][slot];
      const std::uint64_t sequence = image.sequence;
      const std::string problem =
          image_from_message(*static_cast<const sensor_msgs_msg_dds__Image_*>(samples[i]),
                             settings_.cameras[eye], 0, image);
      const std::lock_guard lock(mutex_);
      ++counts_.images_received;
      if (!problem.empty()) {
        image.sequence = sequence;
        if (counts_.images_malformed++ == 0) {
          std::cerr << "cambio node perception: refused an image on /"
                    << settings_.cameras[eye].name << "/image_raw: " << problem << "\n";
        }
        counts_.last_problem = "/" + settings_.cameras[eye].name + "/image_raw: " + problem;
        continue;
      }
      newest_slot_[eye] = slot;
    }
    dds_return_loan(dds_->images[eye], samples, n);
  }
}

bool PerceptionNode::process_newest_pair() {
  // The newest left image with a right one exposed within half a camera period of it.
  const hal::Image* left = nullptr;
  const hal::Image* right = nullptr;
  for (const hal::Image& l : recent_[0]) {
    if (l.sequence == 0 || l.stamp_ns <= last_processed_stamp_ns_) continue;
    if (left != nullptr && l.stamp_ns <= left->stamp_ns) continue;
    for (const hal::Image& r : recent_[1]) {
      if (r.sequence != 0 && std::llabs(l.stamp_ns - r.stamp_ns) <= max_skew_ns_) {
        left = &l;
        right = &r;
      }
    }
  }
  if (left == nullptr) return false;
  last_processed_stamp_ns_ = left->stamp_ns;
  hal::StereoFrame& pair = pairs_->back();
  pair.left = *left;  // Same sizes: copied into the slot's buffers.
  pair.right = *right;
  pairs_->publish();
  const auto now_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                          std::chrono::steady_clock::now().time_since_epoch())
                          .count();
  const hal::LoopTick tick{cycle_++, now_ns, now_ns, 0.0};
  const hal::Status status = server_->update(tick);
  perception::SsmSummary summary;
  const std::lock_guard lock(mutex_);
  if (status != hal::Status::kOk || !server_->summaries().read(summary)) {
    ++counts_.pairs_rejected;
    return true;
  }
  ++counts_.pairs_processed;
  ssm_time_.record_ns(static_cast<std::int64_t>(summary.timings.total_us * 1e3));
  const cambio_msgs_msg_dds__SsmSummary_& message =
      dds_->result->fill(summary, to_ros_time(summary.stamp_ns, 0));
  ++(dds_write(dds_->results, &message) == DDS_RETCODE_OK ? counts_.results_sent
                                                          : counts_.write_errors);
  return true;
}

}  // namespace cambio::ros2
