// The ROS 2 bridge's figures: how long a joint state takes from its sample to a second
// participant's reader (p50/p99), and how many 640x480 rgb8 stereo pairs per second reach a
// reader when the camera side publishes at 30 Hz. Bridge and reader share this process, on
// loopback with the shipped Cyclone configuration; run from the source tree with
// CYCLONEDDS_URI=file://$PWD/firmware_config/ros2/cyclonedds_localhost.xml set. Prints one JSON
// object; the CPU share is the whole process's (bridge, reader and this camera stand-in). The
// latency excludes the bridge's own sampling period (up to 1/joint_states_hz after the loop
// published), which the rate sets; images are sampled newest-wins at 30 Hz of wall time, so a
// pair the camera replaced before the bridge woke is never sent.
#include <dds/dds.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "cambio/ros2/ros2_bridge.hpp"
#include "sensor_msgs/msg/Image.h"
#include "sensor_msgs/msg/JointState.h"

namespace {

std::int64_t now_ns(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return std::int64_t{t.tv_sec} * 1'000'000'000 + t.tv_nsec;
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1))];
}

dds_entity_t reader(dds_entity_t participant, const dds_topic_descriptor_t& type, const char* name,
                    dds_reliability_kind_t reliability) {
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, reliability, DDS_SECS(1));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 100);
  const dds_entity_t topic = dds_create_topic(participant, &type, name, nullptr, nullptr);
  const dds_entity_t r = dds_create_reader(participant, topic, qos, nullptr);
  dds_delete_qos(qos);
  return r;
}

}  // namespace

int main() {
  using namespace cambio;
  const auto domain = static_cast<std::uint32_t>(100 + getpid() % 100);
  constexpr int kJoints = 15;
  constexpr int kWidth = 640;
  constexpr int kHeight = 480;
  constexpr double kSeconds = 5.0;

  hal::TripleBuffer<hal::StereoFrame> stereo(
      hal::StereoFrame{hal::Image(kWidth, kHeight, hal::PixelFormat::kRgb8),
                       hal::Image(kWidth, kHeight, hal::PixelFormat::kRgb8)});
  ros2::BridgeSettings settings;
  settings.domain_id = domain;
  settings.joint_states_rate_hz = 200.0;
  settings.images_rate_hz = 30.0;
  settings.publish_tf = false;
  settings.epoch_offset_ns = now_ns(CLOCK_REALTIME) - now_ns(CLOCK_MONOTONIC);
  ros2::BridgeSources sources;
  for (int j = 0; j < kJoints; ++j) sources.joint_names.push_back("joint_" + std::to_string(j));
  // A joint loop that has just published: the sample is stamped when the bridge takes it.
  sources.joint_states = [](ros2::JointStatesSample& sample) {
    sample.stamp_ns = now_ns(CLOCK_MONOTONIC);
    return true;
  };
  sources.stereo_images = &stereo;
  for (std::size_t eye = 0; eye < 2; ++eye) {
    sources.stereo_cameras[eye].name = eye == 0 ? "left_eye" : "right_eye";
    sources.stereo_cameras[eye].intrinsics.width_px = kWidth;
    sources.stereo_cameras[eye].intrinsics.height_px = kHeight;
  }

  const dds_entity_t participant = dds_create_participant(domain, nullptr, nullptr);
  if (participant < 0) {
    std::fprintf(stderr, "ros2_bridge_bench: %s\n", dds_strretcode(participant));
    return 3;
  }
  const dds_entity_t joints = reader(participant, sensor_msgs_msg_dds__JointState__desc,
                                     "rt/joint_states", DDS_RELIABILITY_RELIABLE);
  const dds_entity_t images = reader(participant, sensor_msgs_msg_dds__Image__desc,
                                     "rt/left_eye/image_raw", DDS_RELIABILITY_BEST_EFFORT);

  ros2::Ros2Bridge bridge(settings, std::move(sources));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // Discovery.
  bridge.start();
  std::vector<double> latency_us;
  std::uint64_t images_received = 0;
  rusage before{};
  getrusage(RUSAGE_SELF, &before);
  const auto start = std::chrono::steady_clock::now();
  auto next_frame = start;
  std::uint64_t sequence = 0;
  while (std::chrono::steady_clock::now() - start < std::chrono::duration<double>(kSeconds)) {
    if (std::chrono::steady_clock::now() >= next_frame) {  // The camera loop at 30 Hz.
      hal::StereoFrame& pair = stereo.back();
      pair.left.sequence = pair.right.sequence = ++sequence;
      pair.left.stamp_ns = pair.right.stamp_ns = now_ns(CLOCK_MONOTONIC);
      stereo.publish();
      next_frame += std::chrono::microseconds(33'333);
    }
    void* samples[32] = {};
    dds_sample_info_t infos[32];
    int n = dds_take(joints, samples, infos, 32, 32);
    const std::int64_t received_ns = now_ns(CLOCK_REALTIME);
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      const auto* m = static_cast<const sensor_msgs_msg_dds__JointState_*>(samples[i]);
      const std::int64_t stamp_ns =
          std::int64_t{m->header.stamp.sec} * 1'000'000'000 + m->header.stamp.nanosec;
      latency_us.push_back(static_cast<double>(received_ns - stamp_ns) * 1e-3);
    }
    if (n > 0) dds_return_loan(joints, samples, n);
    n = dds_take(images, samples, infos, 32, 32);
    for (int i = 0; i < n; ++i) images_received += infos[i].valid_data ? 1 : 0;
    if (n > 0) dds_return_loan(images, samples, n);
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  rusage after{};
  getrusage(RUSAGE_SELF, &after);
  bridge.stop();
  dds_delete(participant);
  auto cpu_s = [](const rusage& r) {
    return static_cast<double>(r.ru_utime.tv_sec + r.ru_stime.tv_sec) +
           static_cast<double>(r.ru_utime.tv_usec + r.ru_stime.tv_usec) * 1e-6;
  };
  const ros2::BridgeCounts counts = bridge.counts();
  std::printf(
      "{\"joint_states\": {\"rate_hz\": 200, \"joints\": %d, \"received\": %zu, "
      "\"latency_p50_us\": %.1f, \"latency_p99_us\": %.1f},\n"
      " \"images\": {\"width\": %d, \"height\": %d, \"encoding\": \"rgb8\", \"camera_hz\": 30, "
      "\"sent_per_s\": %.1f, \"received_per_s\": %.1f},\n"
      " \"process_cpu_share_of_a_core\": %.3f, \"write_errors\": %llu}\n",
      kJoints, latency_us.size(), percentile(latency_us, 0.5), percentile(latency_us, 0.99), kWidth,
      kHeight, static_cast<double>(counts.images) / 2.0 / wall_s,
      static_cast<double>(images_received) / wall_s, (cpu_s(after) - cpu_s(before)) / wall_s,
      static_cast<unsigned long long>(counts.write_errors));
  return 0;
}
