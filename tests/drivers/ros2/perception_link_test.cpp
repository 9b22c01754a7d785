#include <dds/dds.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <thread>

#include "cambio/config/map_reader.hpp"
#include "cambio/perception/perception_config.hpp"
#include "cambio/ros2/perception_link.hpp"
#include "link_messages.hpp"

// The split across machines, in one process: the robot's end of the link and a perception node
// on one DDS domain (kept on loopback). The truth for a result is the same pair through an
// SsmServer in this process, and for the disparity the shift the right image was made with.

namespace cambio::ros2 {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;
constexpr int kShiftPx = 9;  // The right image is the left one moved this far left.

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

hal::CameraInfo camera(const std::string& name) {
  hal::CameraInfo info;
  info.name = name;
  info.intrinsics = {kWidth, kHeight, 500.0, 500.0, 319.5, 239.5};
  info.format = hal::PixelFormat::kGrey8;
  info.rate_hz = 30.0;
  return info;
}

perception::SsmConfig ssm_config() {
  perception::SsmConfig ssm =
      perception::load_ssm_config(perception::default_ssm_config_path(), {});
  ssm.disparity.scan_range_px = 120.0;
  return ssm;
}

// Blocks of random grey (4 px: texture at every level), the right eye's copy moved by kShiftPx:
// a point at x in the left image is at x - kShiftPx in the right one.
hal::StereoFrame textured_pair(std::int64_t stamp_ns, std::uint64_t sequence) {
  std::mt19937 random(7);
  std::uniform_int_distribution<int> grey(20, 235);
  const int block_columns = (kWidth + kShiftPx) / 4 + 1;
  std::vector<std::uint8_t> blocks(static_cast<std::size_t>(block_columns * (kHeight / 4 + 1)));
  for (std::uint8_t& block : blocks) block = static_cast<std::uint8_t>(grey(random));
  const auto texture = [&](int x, int y) {
    return blocks[static_cast<std::size_t>((y / 4) * block_columns + x / 4)];
  };
  hal::StereoFrame pair{hal::Image(kWidth, kHeight, hal::PixelFormat::kGrey8),
                        hal::Image(kWidth, kHeight, hal::PixelFormat::kGrey8)};
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      pair.left.row(y)[x] = texture(x, y);
      pair.right.row(y)[x] = texture(x + kShiftPx, y);
    }
  }
  pair.left.stamp_ns = pair.right.stamp_ns = stamp_ns;
  pair.left.sequence = pair.right.sequence = sequence;
  return pair;
}

perception::SsmRequest centred_request() {
  perception::SsmRequest request;
  request.fixation_set = true;
  request.fixation = {perception::PixelPoint{320, 240}, perception::PixelPoint{320, 240}};
  return request;
}

// What an SsmServer on this machine makes of `pair` with `request`: the peer the node must match.
perception::SsmSummary local_result(const hal::StereoFrame& pair,
                                    const perception::SsmRequest& request) {
  hal::TripleBuffer<hal::StereoFrame> pairs(pair);
  perception::SsmServer server("local", pairs, camera("left_eye"), camera("right_eye"),
                               ssm_config());
  server.configure();
  server.activate();
  server.requests().write(request);
  pairs.back() = pair;
  pairs.publish();
  EXPECT_EQ(server.update({0, 0, 0, 0.0}), hal::Status::kOk);
  perception::SsmSummary summary;
  EXPECT_TRUE(server.summaries().read(summary));
  return summary;
}

class PerceptionLinkTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string config = std::string("file://") + CAMBIO_SOURCE_DIR +
                               "/firmware_config/ros2/cyclonedds_localhost.xml";
    setenv("CYCLONEDDS_URI", config.c_str(), 1);
    domain_ = static_cast<std::uint32_t>(1 + (getpid() + 101) % 200);
  }

  void start_node() {
    PerceptionNodeSettings settings;
    settings.domain_id = domain_;
    settings.cameras = {camera("left_eye"), camera("right_eye")};
    node_ = std::make_unique<PerceptionNode>(settings, ssm_config());
    node_stop_ = false;
    node_thread_ = std::thread([this] { node_->serve(node_stop_, 0.0); });
  }
  void stop_node() {
    node_stop_ = true;
    if (node_thread_.joinable()) node_thread_.join();
  }
  void TearDown() override {
    if (link_) link_->stop();
    stop_node();
  }

  void make_link(double link_timeout_s = 0.3) {
    RobotPerceptionLinkSettings settings;
    settings.domain_id = domain_;
    settings.link_timeout_s = link_timeout_s;
    settings.max_result_age_s = 1.0;
    link_ = std::make_unique<RobotPerceptionLink>(
        settings, steady_ns, pairs_,
        std::array<hal::CameraInfo, 2>{camera("left_eye"), camera("right_eye")}, requests_,
        results_);
  }

  // Sends pairs (new stamps, same content) until a result newer than `after_version` comes back
  // whose fixation is the request's, or `timeout_s` passes.
  std::optional<perception::SsmSummary> result_after(std::uint64_t after_version,
                                                     double timeout_s = 5.0) {
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::milliseconds(static_cast<int>(timeout_s * 1e3));
    while (std::chrono::steady_clock::now() < deadline) {
      pairs_.back() = textured_pair(steady_ns(), ++sequence_);
      pairs_.publish();
      std::this_thread::sleep_for(std::chrono::milliseconds(33));
      perception::SsmSummary summary;
      if (results_.version() > after_version && results_.read(summary) &&
          summary.fixation[0].x == 320) {
        return summary;
      }
    }
    return std::nullopt;
  }

  std::uint32_t domain_ = 0;
  hal::TripleBuffer<hal::StereoFrame> pairs_{textured_pair(0, 0)};
  hal::SeqlockChannel<perception::SsmRequest> requests_;
  hal::SeqlockChannel<perception::SsmSummary> results_;
  std::unique_ptr<RobotPerceptionLink> link_;
  std::unique_ptr<PerceptionNode> node_;
  std::atomic<bool> node_stop_{false};
  std::thread node_thread_;
  std::uint64_t sequence_ = 0;
};

TEST_F(PerceptionLinkTest, AResultCrossesTheWireAsTheLocalSsmMakesIt) {
  start_node();
  make_link();
  ASSERT_TRUE(link_->wait_for_host(10.0)) << "the node and the link never matched";
  requests_.write(centred_request());
  link_->start();
  const std::optional<perception::SsmSummary> remote = result_after(0);
  ASSERT_TRUE(remote.has_value()) << "no result with the request's fixation came back";

  // Against the image's own geometry: the shift the right image was made with.
  EXPECT_TRUE(remote->disparity.valid);
  EXPECT_NEAR(remote->disparity.disparity_px, kShiftPx, 0.25);
  // Against the same pair through an SsmServer here (the node's results are its results).
  const perception::SsmSummary local = local_result(textured_pair(0, 1), centred_request());
  EXPECT_EQ(remote->disparity.disparity_px, local.disparity.disparity_px);
  EXPECT_EQ(remote->disparity.confidence, local.disparity.confidence);
  EXPECT_EQ(remote->disparity.level, local.disparity.level);
  EXPECT_EQ(remote->levels, local.levels);
  for (std::size_t eye = 0; eye < 2; ++eye) {
    for (int k = 0; k < local.levels; ++k) {
      const auto level = static_cast<std::size_t>(k);
      EXPECT_EQ(remote->geometry[eye][level].origin_x_px, local.geometry[eye][level].origin_x_px);
      EXPECT_EQ(remote->moments[eye][level].area_px2, local.moments[eye][level].area_px2);
      EXPECT_EQ(remote->moments[eye][level].centroid_x_px, local.moments[eye][level].centroid_x_px);
    }
  }
  // The stamp went out as ROS time and came back as the run's clock: a recent pair's exposure.
  const double age_s = static_cast<double>(steady_ns() - remote->stamp_ns) * 1e-9;
  EXPECT_GE(age_s, 0.0);
  EXPECT_LT(age_s, 0.5);

  link_->stop();
  const RobotPerceptionLinkCounts counts = link_->counts();
  EXPECT_GE(counts.requests_sent, 1u);
  EXPECT_GE(counts.results_used, 1u);
  EXPECT_EQ(counts.results_malformed, 0u);
  EXPECT_TRUE(counts.outages.empty());
  EXPECT_GT(counts.latency_median_ms, 0.0);
  EXPECT_EQ(node_->counts().images_malformed, 0u);
}

TEST_F(PerceptionLinkTest, ASilentHostIsAnOutageThatEndsWhenAHostAnswersAgain) {
  start_node();
  make_link(0.2);
  ASSERT_TRUE(link_->wait_for_host(10.0));
  requests_.write(centred_request());
  link_->start();
  ASSERT_TRUE(result_after(0).has_value());
  const std::uint64_t sequence_before = [&] {
    perception::SsmSummary summary;
    EXPECT_TRUE(results_.read(summary));
    return summary.sequence;
  }();

  // The host goes away (its process ends): pairs keep going out, nothing comes back.
  stop_node();
  node_.reset();
  const std::uint64_t version = results_.version();
  for (int k = 0; k < 15; ++k) {
    pairs_.back() = textured_pair(steady_ns(), ++sequence_);
    pairs_.publish();
    std::this_thread::sleep_for(std::chrono::milliseconds(33));
  }
  EXPECT_EQ(results_.version(), version) << "a result came from no host";
  RobotPerceptionLinkCounts counts = link_->counts();
  ASSERT_EQ(counts.outages.size(), 1u);
  EXPECT_LT(counts.outages[0].back_s, 0.0) << "the outage ended with no host";

  // A new host (a restarted node numbers its results from 1 again): the link takes its results
  // as new, and the outage ends.
  start_node();
  const std::optional<perception::SsmSummary> after = result_after(version, 10.0);
  ASSERT_TRUE(after.has_value()) << "no result from the restarted host";
  EXPECT_GT(after->sequence, sequence_before);
  counts = link_->counts();
  ASSERT_EQ(counts.outages.size(), 1u);
  EXPECT_GT(counts.outages[0].back_s, counts.outages[0].lost_s + 0.2);
}

// A raw DDS participant on the domain: what a faulty or hostile peer could write.
class RawPeer {
 public:
  explicit RawPeer(std::uint32_t domain) {
    participant_ = dds_create_participant(domain, nullptr, nullptr);
    EXPECT_GT(participant_, 0);
  }
  ~RawPeer() { dds_delete(participant_); }
  dds_entity_t writer(const dds_topic_descriptor_t& type, const std::string& ros_topic,
                      dds_reliability_kind_t reliability, std::int32_t depth,
                      dds_durability_kind_t durability = DDS_DURABILITY_VOLATILE) {
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, reliability, DDS_MSECS(100));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, depth);
    dds_qset_durability(qos, durability);
    const dds_entity_t topic =
        dds_create_topic(participant_, &type, ("rt" + ros_topic).c_str(), qos, nullptr);
    const dds_entity_t writer = dds_create_writer(participant_, topic, qos, nullptr);
    dds_delete_qos(qos);
    EXPECT_GT(writer, 0);
    return writer;
  }

 private:
  dds_entity_t participant_ = 0;
};

bool wait_until(const std::function<bool()>& condition, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::milliseconds(static_cast<int>(timeout_s * 1e3));
  while (std::chrono::steady_clock::now() < deadline) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return condition();
}

TEST_F(PerceptionLinkTest, MalformedResultsAreRefusedAndCountedNeverUsed) {
  make_link();
  link_->start();
  RawPeer peer(domain_);
  const dds_entity_t writer = peer.writer(cambio_msgs_msg_dds__SsmSummary__desc, kSsmSummaryTopic,
                                          DDS_RELIABILITY_RELIABLE, 10);
  ASSERT_TRUE(wait_until(
      [&] {
        dds_publication_matched_status_t status{};
        return dds_get_publication_matched_status(writer, &status) == DDS_RETCODE_OK &&
               status.current_count > 0;
      },
      10.0));
  const RosTime now = to_ros_time(steady_ns());
  auto message = [&] {
    cambio_msgs_msg_dds__SsmSummary_ m{};
    m.header.stamp = {now.sec, now.nanosec};
    m.header.frame_id = const_cast<char*>("left_eye_optical_frame");
    m.levels = 4;
    m.disparity.valid = true;
    m.disparity.confidence = 0.9f;
    m.disparity.level = 0;
    return m;
  };
  cambio_msgs_msg_dds__SsmSummary_ nan_disparity = message();
  nan_disparity.disparity.disparity_px = std::nanf("");
  cambio_msgs_msg_dds__SsmSummary_ too_many_levels = message();
  too_many_levels.levels = 99;
  cambio_msgs_msg_dds__SsmSummary_ confidence_beyond_one = message();
  confidence_beyond_one.disparity.confidence = 2.0f;
  cambio_msgs_msg_dds__SsmSummary_ infinite_flow = message();
  infinite_flow.motion[1].key_flow_x_px = INFINITY;
  cambio_msgs_msg_dds__SsmSummary_ nan_region = message();
  nan_region.region.valid = true;
  nan_region.region.cells = 40;
  nan_region.region.centroid_x_px = std::nanf("");
  std::array<cambio_msgs_msg_dds__Moments_, 6> moments{};
  cambio_msgs_msg_dds__SsmSummary_ moments_beyond_levels = message();
  moments_beyond_levels.left_moments = {6, 6, moments.data(), false};
  for (const auto* bad : {&nan_disparity, &too_many_levels, &confidence_beyond_one, &infinite_flow,
                          &nan_region, &moments_beyond_levels}) {
    ASSERT_EQ(dds_write(writer, bad), DDS_RETCODE_OK);
  }
  ASSERT_TRUE(wait_until([&] { return link_->counts().results_received >= 6; }, 10.0));
  const RobotPerceptionLinkCounts counts = link_->counts();
  EXPECT_EQ(counts.results_malformed, 6u);
  EXPECT_EQ(counts.results_used, 0u);
  EXPECT_EQ(results_.version(), 0u) << "a malformed result reached the gaze loop's channel";
  EXPECT_NE(counts.last_malformed.find("levels"), std::string::npos) << counts.last_malformed;

  // A well-formed one after them is used.
  const cambio_msgs_msg_dds__SsmSummary_ good = message();
  ASSERT_EQ(dds_write(writer, &good), DDS_RETCODE_OK);
  ASSERT_TRUE(wait_until([&] { return link_->counts().results_used == 1; }, 10.0));
}

TEST_F(PerceptionLinkTest, TheNodeRefusesMalformedImagesAndRequestsAndKeepsServing) {
  start_node();
  RawPeer peer(domain_);
  const dds_entity_t left = peer.writer(sensor_msgs_msg_dds__Image__desc, "/left_eye/image_raw",
                                        DDS_RELIABILITY_RELIABLE, 2);
  const dds_entity_t request =
      peer.writer(cambio_msgs_msg_dds__SsmRequest__desc, kSsmRequestTopic, DDS_RELIABILITY_RELIABLE,
                  1, DDS_DURABILITY_TRANSIENT_LOCAL);
  ASSERT_TRUE(wait_until(
      [&] {
        dds_publication_matched_status_t a{};
        dds_publication_matched_status_t b{};
        return dds_get_publication_matched_status(left, &a) == DDS_RETCODE_OK &&
               dds_get_publication_matched_status(request, &b) == DDS_RETCODE_OK &&
               a.current_count > 0 && b.current_count > 0;
      },
      10.0));
  const hal::StereoFrame pair = textured_pair(steady_ns(), 1);
  const std::string frame = "left_eye_optical_frame";
  const RosTime stamp = to_ros_time(pair.left.stamp_ns);

  hal::Image small(320, 240, hal::PixelFormat::kGrey8);
  sensor_msgs_msg_dds__Image_ wrong_size = image_message(small, frame, stamp);
  sensor_msgs_msg_dds__Image_ wrong_encoding = image_message(pair.left, frame, stamp);
  wrong_encoding.encoding = const_cast<char*>("bgr8");
  sensor_msgs_msg_dds__Image_ short_data = image_message(pair.left, frame, stamp);
  short_data.data._length /= 2;
  sensor_msgs_msg_dds__Image_ wrong_step = image_message(pair.left, frame, stamp);
  wrong_step.step = 1;
  for (const sensor_msgs_msg_dds__Image_* bad :
       {&wrong_size, &wrong_encoding, &short_data, &wrong_step}) {
    ASSERT_EQ(dds_write(left, bad), DDS_RETCODE_OK);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  perception::SsmRequest far_fixation = centred_request();
  far_fixation.fixation[1] = {5000, 240};
  const cambio_msgs_msg_dds__SsmRequest_ bad_request =
      request_message(far_fixation, to_ros_time(steady_ns()));
  ASSERT_EQ(dds_write(request, &bad_request), DDS_RETCODE_OK);
  ASSERT_TRUE(wait_until(
      [&] {
        const PerceptionNodeCounts c = node_->counts();
        return c.images_received >= 4 && c.requests_received >= 1;
      },
      10.0));
  PerceptionNodeCounts counts = node_->counts();
  EXPECT_EQ(counts.images_malformed, 4u);
  EXPECT_EQ(counts.requests_malformed, 1u);
  EXPECT_NE(counts.last_problem.find("more than an image's size outside"), std::string::npos)
      << counts.last_problem;
  EXPECT_EQ(counts.pairs_processed, 0u);

  // The robot's own link after all that: its pairs are still served.
  make_link();
  ASSERT_TRUE(link_->wait_for_host(10.0));
  requests_.write(centred_request());
  link_->start();
  const std::optional<perception::SsmSummary> result = result_after(0);
  ASSERT_TRUE(result.has_value());
  EXPECT_NEAR(result->disparity.disparity_px, kShiftPx, 0.25);
}

TEST(LinkMessages, ARequestCrossesWithEveryFeatureFlag) {
  perception::SsmRequest in;
  in.fixation_set = true;
  in.fixation = {perception::PixelPoint{300, 200}, perception::PixelPoint{310, 201}};
  in.features.maps = 0b1011;
  in.features.disparity = false;
  in.features.motion = true;
  in.features.moments = false;
  in.features.region = true;
  hal::CameraIntrinsics image;
  image.width_px = 640;
  image.height_px = 480;
  perception::SsmRequest out;
  ASSERT_EQ(request_from_message(request_message(in, to_ros_time(0)), image, out), "");
  EXPECT_TRUE(out.fixation_set);
  EXPECT_EQ(out.fixation[1].x, 310);
  EXPECT_EQ(out.features.maps, in.features.maps);
  EXPECT_FALSE(out.features.disparity);
  EXPECT_TRUE(out.features.motion);
  EXPECT_FALSE(out.features.moments);
  EXPECT_TRUE(out.features.region);
}

TEST(LinkMessages, ASummaryCrossesEveryFieldIntact) {
  perception::SsmSummary in;
  in.sequence = 41;
  in.stamp_ns = 1'700'000'000'123'456'789;
  in.levels = 5;
  in.fixation = {perception::PixelPoint{301, 222}, perception::PixelPoint{287, 219}};
  float value = 0.5f;
  for (std::size_t eye = 0; eye < 2; ++eye) {
    for (std::size_t k = 0; k < 5; ++k) {
      in.geometry[eye][k] = {1 << k, static_cast<int>(eye * 10 + k), -static_cast<int>(k), value};
      in.moments[eye][k] = {true,      value,     value + 1, value + 2, value + 3,
                            value + 4, value + 5, 0.25,      0.5};
      in.motion[eye].per_level[k] = {true,      value, -value,    value * 2,
                                     value * 3, 3,     value * 4, -value};
      value += 0.25f;
    }
    in.motion[eye].valid = true;
    in.motion[eye].fixation_changed = eye == 1;
    in.motion[eye].flow_x_px = 1.5f;
    in.motion[eye].flow_y_px = -2.5f;
    in.motion[eye].level = 1;
    in.motion[eye].key_valid = true;
    in.motion[eye].key_flow_x_px = 4.25f;
    in.motion[eye].key_flow_y_px = -0.75f;
    in.motion[eye].frame = 99;
    in.motion[eye].key_frame = 90;
    in.motion[eye].one_directional = eye == 0;
    in.motion[eye].gradient_orientation_rad = 1.25f;
  }
  in.region = {true, true, 57, 12.5f, -3.25f, -40.0f, 48.0f, -24.0f, 16.0f};
  in.disparity.valid = true;
  in.disparity.disparity_px = -12.375f;
  in.disparity.confidence = 0.875f;
  in.disparity.level = 1;
  in.disparity.levels = 5;
  in.disparity.candidates = 3;
  in.disparity.scan_window_tier = 2;
  for (std::size_t k = 0; k < 5; ++k) {
    in.disparity.per_level[k] = {true,
                                 k != 2,
                                 k == 3,
                                 k == 4,
                                 0.5f,
                                 -12.0f + static_cast<float>(k),
                                 0.75f,
                                 0.9f,
                                 12.5f,
                                 1 << k,
                                 -20,
                                 20,
                                 static_cast<int>(k)};
  }
  in.timings = {1, 2, 3, 4, 5, 15, 0.5};

  SsmSummaryMessage message("left_eye_optical_frame");
  const std::int64_t offset_ns = 1'000'000'000;
  perception::SsmSummary out;
  ASSERT_EQ(
      summary_from_message(message.fill(in, to_ros_time(in.stamp_ns, offset_ns)), offset_ns, out),
      "");
  EXPECT_EQ(out.stamp_ns, in.stamp_ns);
  EXPECT_EQ(out.levels, in.levels);
  EXPECT_EQ(out.fixation[1].x, 287);
  for (std::size_t eye = 0; eye < 2; ++eye) {
    for (std::size_t k = 0; k < 5; ++k) {
      EXPECT_EQ(out.geometry[eye][k].scale_px, in.geometry[eye][k].scale_px);
      EXPECT_EQ(out.geometry[eye][k].origin_x_px, in.geometry[eye][k].origin_x_px);
      EXPECT_EQ(out.geometry[eye][k].fraction_inside, in.geometry[eye][k].fraction_inside);
      EXPECT_EQ(out.moments[eye][k].mu11_px2, in.moments[eye][k].mu11_px2);
      EXPECT_EQ(out.moments[eye][k].eccentricity, in.moments[eye][k].eccentricity);
      EXPECT_EQ(out.motion[eye].per_level[k].residual_rms,
                in.motion[eye].per_level[k].residual_rms);
      EXPECT_EQ(out.motion[eye].per_level[k].iterations, 3);
      EXPECT_EQ(out.motion[eye].per_level[k].max_eigenvalue,
                in.motion[eye].per_level[k].max_eigenvalue);
      EXPECT_EQ(out.motion[eye].per_level[k].gradient_orientation_rad,
                in.motion[eye].per_level[k].gradient_orientation_rad);
    }
    EXPECT_EQ(out.motion[eye].one_directional, eye == 0);
    EXPECT_EQ(out.motion[eye].gradient_orientation_rad, 1.25f);
    EXPECT_EQ(out.motion[eye].fixation_changed, eye == 1);
    EXPECT_EQ(out.motion[eye].key_flow_x_px, 4.25f);
    EXPECT_EQ(out.motion[eye].key_frame, 90u);
  }
  EXPECT_EQ(out.disparity.disparity_px, -12.375f);
  EXPECT_EQ(out.disparity.scan_window_tier, 2);
  EXPECT_EQ(out.disparity.candidates, 3);
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(out.disparity.per_level[k].valid, k != 2);
    EXPECT_EQ(out.disparity.per_level[k].at_range_edge, k == 3);
    EXPECT_EQ(out.disparity.per_level[k].aperture, k == 4);
    EXPECT_EQ(out.disparity.per_level[k].disparity_px, -12.0f + static_cast<float>(k));
    EXPECT_EQ(out.disparity.per_level[k].moved_windows, static_cast<int>(k));
  }
  EXPECT_EQ(out.timings.total_us, 15.0);
  EXPECT_EQ(out.timings.region_us, 0.5);
  EXPECT_TRUE(out.region.valid);
  EXPECT_TRUE(out.region.clipped);
  EXPECT_EQ(out.region.cells, 57);
  EXPECT_EQ(out.region.centroid_x_px, 12.5f);
  EXPECT_EQ(out.region.centroid_y_px, -3.25f);
  EXPECT_EQ(out.region.left_px, -40.0f);
  EXPECT_EQ(out.region.bottom_px, 16.0f);
}

}  // namespace
}  // namespace cambio::ros2
