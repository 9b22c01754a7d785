#include <dds/dds.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

#include "../../apps/run_cambio.hpp"
#include "diagnostic_msgs/msg/DiagnosticArray.h"
#include "geometry_msgs/msg/PointStamped.h"
#include "rmw_dds_common/msg/ParticipantEntitiesInfo.h"
#include "rosgraph_msgs/msg/Clock.h"
#include "sensor_msgs/msg/CameraInfo.h"
#include "sensor_msgs/msg/Image.h"
#include "sensor_msgs/msg/JointState.h"
#include "std_msgs/msg/String.h"
#include "tf2_msgs/msg/TFMessage.h"
#include "trajectory_msgs/msg/JointTrajectory.h"

// A second process on the DDS domain, as a ROS 2 node would be: it discovers what `cambio run`
// publishes by DDS's own discovery (the names and QoS ROS 2 matches on) and reads the messages
// with types generated from ROS 2's .msg files. The truth for the values is the experiment's
// closed-form geometry, not the run's own report.

namespace cambio {
namespace {

constexpr double kDegPerRad = 180.0 / M_PI;

using Guid = std::array<std::uint8_t, 16>;

struct Publication {
  std::string type_name;
  Guid key{};              ///< The writer's GUID, from DDS discovery.
  Guid participant_key{};  ///< Its participant's.
  dds_reliability_kind_t reliability = DDS_RELIABILITY_BEST_EFFORT;
  dds_history_kind_t history = DDS_HISTORY_KEEP_ALL;
  int32_t depth = 0;
  dds_durability_kind_t durability = DDS_DURABILITY_VOLATILE;
};

struct ReceivedTransform {
  double stamp_s = 0.0;
  std::string parent;
  Eigen::Isometry3d X_PC = Eigen::Isometry3d::Identity();
};
using ReceivedTf = std::map<std::string, ReceivedTransform>;  // By child frame.

struct ReceivedImage {
  double stamp_s = 0.0;
  std::string frame_id;
  std::string encoding;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint32_t step = 0;
  std::size_t bytes = 0;
  double mean_level = 0.0;
  double level_spread = 0.0;  // Max minus min: a blank frame has none.
};

struct ReceivedCameraInfo {
  std::string frame_id;
  std::string distortion_model;
  std::size_t distortion_count = 0;
  std::array<double, 9> k{};
  std::array<double, 12> p{};
};

struct ReceivedStatus {
  int level = -1;
  std::string name;
  std::string message;
  std::string hardware_id;
  std::map<std::string, std::string> values;
};

ReceivedStatus received_status(const diagnostic_msgs_msg_dds__DiagnosticStatus_& m) {
  ReceivedStatus r;
  r.level = m.level;
  r.name = m.name;
  r.message = m.message;
  r.hardware_id = m.hardware_id;
  for (uint32_t k = 0; k < m.values._length; ++k) {
    r.values[m.values._buffer[k].key] = m.values._buffer[k].value;
  }
  return r;
}

struct ReceivedJointState {
  double stamp_s = 0.0;
  std::vector<std::string> names;
  std::vector<double> position_rad;
  std::size_t velocities = 0;
  std::size_t efforts = 0;
};

double seconds(const builtin_interfaces_msg_dds__Time_& t) {
  return t.sec + t.nanosec * 1e-9;
}

ReceivedTf received_tf(const tf2_msgs_msg_dds__TFMessage_& message) {
  ReceivedTf tf;
  for (uint32_t i = 0; i < message.transforms._length; ++i) {
    const geometry_msgs_msg_dds__TransformStamped_& t = message.transforms._buffer[i];
    const auto& p = t.transform.translation;
    const auto& q = t.transform.rotation;
    ReceivedTransform r;
    r.stamp_s = seconds(t.header.stamp);
    r.parent = t.header.frame_id;
    r.X_PC.translation() = Eigen::Vector3d(p.x, p.y, p.z);
    r.X_PC.linear() = Eigen::Quaterniond(q.w, q.x, q.y, q.z).toRotationMatrix();
    tf[t.child_frame_id] = r;
  }
  return tf;
}

// The pose of `frame` in `root`, following the parents tf names.
Eigen::Isometry3d pose_in(const ReceivedTf& tf, const std::string& root, std::string frame) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  while (frame != root) {
    const auto at = tf.find(frame);
    if (at == tf.end()) {
      ADD_FAILURE() << "no transform to " << frame;
      return X;
    }
    X = at->second.X_PC * X;
    frame = at->second.parent;
  }
  return X;
}

// The peer's side of the domain: readers for /joint_states and /clock, and DDS's built-in
// topic of publications (what ROS 2's `ros2 topic list -t` shows).
class Peer {
 public:
  explicit Peer(dds_domainid_t domain) {
    participant_ = dds_create_participant(domain, nullptr, nullptr);
    EXPECT_GT(participant_, 0) << dds_strretcode(participant_);
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
    const dds_entity_t joint_topic = dds_create_topic(
        participant_, &sensor_msgs_msg_dds__JointState__desc, "rt/joint_states", nullptr, nullptr);
    const dds_entity_t clock_topic = dds_create_topic(
        participant_, &rosgraph_msgs_msg_dds__Clock__desc, "rt/clock", nullptr, nullptr);
    joint_reader_ = dds_create_reader(participant_, joint_topic, qos, nullptr);
    clock_reader_ = dds_create_reader(participant_, clock_topic, qos, nullptr);
    const dds_entity_t tf_topic = dds_create_topic(participant_, &tf2_msgs_msg_dds__TFMessage__desc,
                                                   "rt/tf", nullptr, nullptr);
    const dds_entity_t tf_static_topic = dds_create_topic(
        participant_, &tf2_msgs_msg_dds__TFMessage__desc, "rt/tf_static", nullptr, nullptr);
    tf_reader_ = dds_create_reader(participant_, tf_topic, qos, nullptr);
    dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
    tf_static_reader_ = dds_create_reader(participant_, tf_static_topic, qos, nullptr);
    description_reader_ =
        dds_create_reader(participant_,
                          dds_create_topic(participant_, &std_msgs_msg_dds__String__desc,
                                           "rt/robot_description", nullptr, nullptr),
                          qos, nullptr);
    dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
    look_at_writer_ =
        dds_create_writer(participant_,
                          dds_create_topic(participant_, &geometry_msgs_msg_dds__PointStamped__desc,
                                           "rt/cambio/look_at", nullptr, nullptr),
                          qos, nullptr);
    command_writer_ =
        dds_create_writer(participant_,
                          dds_create_topic(participant_, &std_msgs_msg_dds__String__desc,
                                           "rt/cambio/command", nullptr, nullptr),
                          qos, nullptr);
    // A million-point trajectory is 32 MB on the wire: the next write may wait for it.
    trajectory_writer_ =
        reliable_writer(&trajectory_msgs_msg_dds__JointTrajectory__desc,
                        "rt/cambio/joint_trajectory", DDS_SECS(30), DDS_HISTORY_KEEP_ALL, 0);
    // What a ROS 2 publisher with the default QoS is: reliable keep-last 10, never blocking.
    flood_writer_ = reliable_writer(&geometry_msgs_msg_dds__PointStamped__desc, "rt/cambio/look_at",
                                    DDS_MSECS(100), DDS_HISTORY_KEEP_LAST, 10);
    refusal_reader_ =
        dds_create_reader(participant_,
                          dds_create_topic(participant_, &std_msgs_msg_dds__String__desc,
                                           "rt/cambio/refusals", nullptr, nullptr),
                          qos, nullptr);
    // Sensor data as ROS 2 sends it: best effort.
    dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
    image_reader_ =
        dds_create_reader(participant_,
                          dds_create_topic(participant_, &sensor_msgs_msg_dds__Image__desc,
                                           "rt/left_eye/image_raw", nullptr, nullptr),
                          qos, nullptr);
    camera_info_reader_ =
        dds_create_reader(participant_,
                          dds_create_topic(participant_, &sensor_msgs_msg_dds__CameraInfo__desc,
                                           "rt/left_eye/camera_info", nullptr, nullptr),
                          qos, nullptr);
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    diagnostics_reader_ = dds_create_reader(
        participant_,
        dds_create_topic(participant_, &diagnostic_msgs_msg_dds__DiagnosticArray__desc,
                         "rt/diagnostics", nullptr, nullptr),
        qos, nullptr);
    gaze_status_reader_ = dds_create_reader(
        participant_,
        dds_create_topic(participant_, &diagnostic_msgs_msg_dds__DiagnosticStatus__desc,
                         "rt/cambio/gaze/status", nullptr, nullptr),
        qos, nullptr);
    fixation_reader_ =
        dds_create_reader(participant_,
                          dds_create_topic(participant_, &geometry_msgs_msg_dds__PointStamped__desc,
                                           "rt/cambio/gaze/fixation", nullptr, nullptr),
                          qos, nullptr);
    publications_ =
        dds_create_reader(participant_, DDS_BUILTIN_TOPIC_DCPSPUBLICATION, nullptr, nullptr);
    {
      // As a ROS 2 node's graph cache reads it (rmw_cyclonedds: reliable, transient-local, 1).
      dds_qos_t* graph = dds_create_qos();
      dds_qset_reliability(graph, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
      dds_qset_history(graph, DDS_HISTORY_KEEP_LAST, 1);
      dds_qset_durability(graph, DDS_DURABILITY_TRANSIENT_LOCAL);
      discovery_reader_ = dds_create_reader(
          participant_,
          dds_create_topic(participant_, &rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc,
                           "ros_discovery_info", nullptr, nullptr),
          graph, nullptr);
      dds_delete_qos(graph);
    }
    dds_delete_qos(qos);
    EXPECT_GT(joint_reader_, 0);
    EXPECT_GT(clock_reader_, 0);
    EXPECT_GT(publications_, 0);
    EXPECT_GT(discovery_reader_, 0) << dds_strretcode(discovery_reader_);
  }
  ~Peer() { dds_delete(participant_); }
  Peer(const Peer&) = delete;
  Peer& operator=(const Peer&) = delete;

  void take() {
    constexpr int kBatch = 64;
    void* samples[kBatch] = {};
    dds_sample_info_t infos[kBatch];
    int n = 0;
    while ((n = dds_take(joint_reader_, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto* m = static_cast<const sensor_msgs_msg_dds__JointState_*>(samples[i]);
        ReceivedJointState r;
        r.stamp_s = seconds(m->header.stamp);
        for (uint32_t j = 0; j < m->name._length; ++j) r.names.emplace_back(m->name._buffer[j]);
        r.position_rad.assign(m->position._buffer, m->position._buffer + m->position._length);
        r.velocities = m->velocity._length;
        r.efforts = m->effort._length;
        joint_states.push_back(std::move(r));
      }
      dds_return_loan(joint_reader_, samples, n);
    }
    while ((n = dds_take(clock_reader_, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        clock_s.push_back(
            seconds(static_cast<const rosgraph_msgs_msg_dds__Clock_*>(samples[i])->clock));
      }
      dds_return_loan(clock_reader_, samples, n);
    }
    while ((n = dds_take(tf_reader_, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        tf.push_back(received_tf(*static_cast<const tf2_msgs_msg_dds__TFMessage_*>(samples[i])));
      }
      dds_return_loan(tf_reader_, samples, n);
    }
    while ((n = dds_take(tf_static_reader_, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        tf_static.push_back(
            received_tf(*static_cast<const tf2_msgs_msg_dds__TFMessage_*>(samples[i])));
      }
      dds_return_loan(tf_static_reader_, samples, n);
    }
    while ((n = dds_take(image_reader_, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto* m = static_cast<const sensor_msgs_msg_dds__Image_*>(samples[i]);
        ReceivedImage r;
        r.stamp_s = seconds(m->header.stamp);
        r.frame_id = m->header.frame_id;
        r.encoding = m->encoding;
        r.width = m->width;
        r.height = m->height;
        r.step = m->step;
        r.bytes = m->data._length;
        const std::uint8_t* data = m->data._buffer;
        if (r.bytes > 0) {
          const auto [low, high] = std::minmax_element(data, data + r.bytes);
          r.level_spread = *high - *low;
          r.mean_level = std::accumulate(data, data + r.bytes, 0.0) / static_cast<double>(r.bytes);
        }
        images.push_back(r);
      }
      dds_return_loan(image_reader_, samples, n);
    }
    while ((n = dds_take(camera_info_reader_, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto* m = static_cast<const sensor_msgs_msg_dds__CameraInfo_*>(samples[i]);
        ReceivedCameraInfo r;
        r.frame_id = m->header.frame_id;
        r.distortion_model = m->distortion_model;
        r.distortion_count = m->d._length;
        std::copy(m->k, m->k + 9, r.k.begin());
        std::copy(m->p, m->p + 12, r.p.begin());
        camera_infos.push_back(r);
      }
      dds_return_loan(camera_info_reader_, samples, n);
    }
    while ((n = dds_take(description_reader_, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        robot_description = static_cast<const std_msgs_msg_dds__String_*>(samples[i])->data;
      }
      dds_return_loan(description_reader_, samples, n);
    }
    while ((n = dds_take(refusal_reader_, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        refusals.emplace_back(static_cast<const std_msgs_msg_dds__String_*>(samples[i])->data);
      }
      dds_return_loan(refusal_reader_, samples, n);
    }
    while ((n = dds_take(diagnostics_reader_, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto* m = static_cast<const diagnostic_msgs_msg_dds__DiagnosticArray_*>(samples[i]);
        std::vector<ReceivedStatus> array;
        for (uint32_t k = 0; k < m->status._length; ++k) {
          array.push_back(received_status(m->status._buffer[k]));
        }
        diagnostics.push_back(std::move(array));
      }
      dds_return_loan(diagnostics_reader_, samples, n);
    }
    while ((n = dds_take(gaze_status_reader_, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        gaze_status.push_back(received_status(
            *static_cast<const diagnostic_msgs_msg_dds__DiagnosticStatus_*>(samples[i])));
      }
      dds_return_loan(gaze_status_reader_, samples, n);
    }
    while ((n = dds_take(fixation_reader_, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto* m = static_cast<const geometry_msgs_msg_dds__PointStamped_*>(samples[i]);
        fixation_frames.emplace_back(m->header.frame_id);
        fixations.emplace_back(m->point.x, m->point.y, m->point.z);
      }
      dds_return_loan(fixation_reader_, samples, n);
    }
    while ((n = dds_take(discovery_reader_, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto* m =
            static_cast<const rmw_dds_common_msg_dds__ParticipantEntitiesInfo_*>(samples[i]);
        const auto guid = [](const rmw_dds_common_msg_dds__Gid_& gid) {
          Guid g{};
          std::copy(gid.data, gid.data + g.size(), g.begin());
          return g;
        };
        for (uint32_t k = 0; k < m->node_entities_info_seq._length; ++k) {
          const auto& node = m->node_entities_info_seq._buffer[k];
          GraphNode entry{guid(m->gid), node.node_namespace, node.node_name, {}, {}};
          for (uint32_t w = 0; w < node.writer_gid_seq._length; ++w)
            entry.writers.push_back(guid(node.writer_gid_seq._buffer[w]));
          for (uint32_t r = 0; r < node.reader_gid_seq._length; ++r)
            entry.readers.push_back(guid(node.reader_gid_seq._buffer[r]));
          graph_nodes.push_back(entry);
        }
      }
      dds_return_loan(discovery_reader_, samples, n);
    }
    while ((n = dds_take(publications_, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto* e = static_cast<const dds_builtintopic_endpoint_t*>(samples[i]);
        Publication p;
        p.type_name = e->type_name;
        std::copy(std::begin(e->key.v), std::end(e->key.v), p.key.begin());
        std::copy(std::begin(e->participant_key.v), std::end(e->participant_key.v),
                  p.participant_key.begin());
        dds_duration_t blocking = 0;
        dds_qget_reliability(e->qos, &p.reliability, &blocking);
        dds_qget_history(e->qos, &p.history, &p.depth);
        dds_qget_durability(e->qos, &p.durability);
        publications[e->topic_name] = p;
      }
      dds_return_loan(publications_, samples, n);
    }
  }

  /// A node on ros_discovery_info: its participant's GID, name, and endpoints' GIDs.
  struct GraphNode {
    Guid participant;
    std::string node_namespace;
    std::string name;
    std::vector<Guid> writers;
    std::vector<Guid> readers;
  };
  std::vector<GraphNode> graph_nodes;
  std::vector<ReceivedJointState> joint_states;
  std::vector<double> clock_s;
  std::vector<ReceivedTf> tf;
  std::vector<ReceivedTf> tf_static;
  std::vector<ReceivedImage> images;
  std::vector<ReceivedCameraInfo> camera_infos;
  std::vector<std::string> refusals;
  std::string robot_description;
  std::vector<std::vector<ReceivedStatus>> diagnostics;
  std::vector<ReceivedStatus> gaze_status;
  std::vector<Eigen::Vector3d> fixations;
  std::vector<std::string> fixation_frames;

  /// Sends a look-at target on /cambio/look_at, as a ROS 2 node's PointStamped.
  void look_at(const char* frame, double x, double y, double z) {
    geometry_msgs_msg_dds__PointStamped_ message{};
    message.header.frame_id = const_cast<char*>(frame);
    message.point = {x, y, z};
    EXPECT_EQ(dds_write(look_at_writer_, &message), DDS_RETCODE_OK);
  }
  /// Takes for another half second: what the run's writers linger to deliver after it ended.
  void drain() {
    for (int i = 0; i < 25; ++i) {
      take();
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  /// Writes `count` look-at targets at once (as fast as DDS takes them); returns how many went.
  int flood_look_at(int count, double x, double y, double z) {
    geometry_msgs_msg_dds__PointStamped_ message{};
    message.header.frame_id = const_cast<char*>("base");
    message.point = {x, y, z};
    int sent = 0;
    for (int i = 0; i < count; ++i) sent += dds_write(flood_writer_, &message) == DDS_RETCODE_OK;
    return sent;
  }
  /// Sends a console line on /cambio/command, as a ROS 2 node's std_msgs/String.
  void command(const std::string& line) {
    const std_msgs_msg_dds__String_ message{const_cast<char*>(line.c_str())};
    EXPECT_EQ(dds_write(command_writer_, &message), DDS_RETCODE_OK);
  }
  /// Sends a joint trajectory on /cambio/joint_trajectory: `points` rows of (time from start,
  /// one position per joint), velocities (one row per point) or none.
  void trajectory(std::vector<std::string> joints, const std::vector<std::vector<double>>& points,
                  std::vector<std::vector<double>> velocities = {}) {
    std::vector<char*> names;
    for (std::string& joint : joints) names.push_back(joint.data());
    std::vector<trajectory_msgs_msg_dds__JointTrajectoryPoint_> rows(points.size());
    std::vector<std::vector<double>> positions(points.size());
    for (std::size_t k = 0; k < points.size(); ++k) {
      positions[k].assign(points[k].begin() + 1, points[k].end());
      const double t = points[k][0];
      rows[k].time_from_start.sec = static_cast<int32_t>(std::floor(t));
      rows[k].time_from_start.nanosec =
          static_cast<uint32_t>(std::lround((t - std::floor(t)) * 1e9));
      rows[k].positions = {static_cast<uint32_t>(positions[k].size()),
                           static_cast<uint32_t>(positions[k].size()), positions[k].data(), false};
      if (!velocities.empty()) {
        rows[k].velocities = {static_cast<uint32_t>(velocities[k].size()),
                              static_cast<uint32_t>(velocities[k].size()), velocities[k].data(),
                              false};
      }
    }
    trajectory_msgs_msg_dds__JointTrajectory_ message{};
    message.header.frame_id = const_cast<char*>("");
    message.joint_names = {static_cast<uint32_t>(names.size()), static_cast<uint32_t>(names.size()),
                           names.data(), false};
    message.points = {static_cast<uint32_t>(rows.size()), static_cast<uint32_t>(rows.size()),
                      rows.data(), false};
    EXPECT_EQ(dds_write(trajectory_writer_, &message), DDS_RETCODE_OK);
  }
  /// The newest joint state's position of `joint` (NaN before any).
  double position_rad(const std::string& joint) const {
    if (joint_states.empty()) return std::nan("");
    const ReceivedJointState& state = joint_states.back();
    const auto it = std::find(state.names.begin(), state.names.end(), joint);
    return it != state.names.end()
               ? state.position_rad[static_cast<std::size_t>(it - state.names.begin())]
               : std::nan("");
  }
  bool refused(const std::string& what) const {
    return std::any_of(refusals.begin(), refusals.end(),
                       [&](const std::string& r) { return r.find(what) != std::string::npos; });
  }
  std::map<std::string, Publication> publications;

 private:
  dds_entity_t reliable_writer(const dds_topic_descriptor_t* type, const char* topic,
                               dds_duration_t max_blocking, dds_history_kind_t history,
                               int32_t depth) {
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, max_blocking);
    dds_qset_history(qos, history, depth);
    const dds_entity_t writer = dds_create_writer(
        participant_, dds_create_topic(participant_, type, topic, nullptr, nullptr), qos, nullptr);
    dds_delete_qos(qos);
    return writer;
  }

  dds_entity_t participant_ = 0;
  dds_entity_t joint_reader_ = 0;
  dds_entity_t clock_reader_ = 0;
  dds_entity_t tf_reader_ = 0;
  dds_entity_t tf_static_reader_ = 0;
  dds_entity_t image_reader_ = 0;
  dds_entity_t look_at_writer_ = 0;
  dds_entity_t command_writer_ = 0;
  dds_entity_t flood_writer_ = 0;
  dds_entity_t trajectory_writer_ = 0;
  dds_entity_t refusal_reader_ = 0;
  dds_entity_t description_reader_ = 0;
  dds_entity_t camera_info_reader_ = 0;
  dds_entity_t diagnostics_reader_ = 0;
  dds_entity_t gaze_status_reader_ = 0;
  dds_entity_t fixation_reader_ = 0;
  dds_entity_t publications_ = 0;
  dds_entity_t discovery_reader_ = 0;
};

class Ros2Wire : public ::testing::Test {
 protected:
  void SetUp() override {
    // Loopback only, so parallel tests and other hosts never meet; a domain of this process's
    // own keeps concurrent runs of this test apart.
    const std::string config = std::string("file://") + CAMBIO_SOURCE_DIR +
                               "/firmware_config/ros2/cyclonedds_localhost.xml";
    setenv("CYCLONEDDS_URI", config.c_str(), 1);
    domain_ = static_cast<dds_domainid_t>(1 + getpid() % 200);
    out_ =
        std::filesystem::temp_directory_path() / ("cambio_ros2_wire_" + std::to_string(getpid()));
  }
  void TearDown() override { std::filesystem::remove_all(out_); }

  /// A 4 s gaze run on the wall clock (so that a peer has time to be heard) with no gaze
  /// commands of its own: ROS 2's are its commands. Returns the experiment file.
  std::filesystem::path write_commanded_experiment(const std::string& name) {
    std::filesystem::create_directories(out_);
    const std::filesystem::path experiment = out_ / (name + ".yaml");
    const std::string shipped = std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/";
    std::ofstream file(experiment);
    file << "experiment:\n  name: " << name << "\n  rig: " << shipped
         << "rigs/cambio.yaml\n  scene: " << shipped
         << "scenes/vergence.yaml\n  perception: " << shipped
         << "perception/vergence.yaml\n  executor: realtime\n  duration_s: 4\n  task: gaze\n"
         << "  ros2: {domain_id: " << domain_ << ", commands: true, images_hz: 0}\n";
    EXPECT_TRUE(file.good());
    return experiment;
  }

  dds_domainid_t domain_ = 0;
  std::filesystem::path out_;
};

TEST_F(Ros2Wire, APeerSeesTheVergenceRunsJointsAndTreeUnderRos2sNamesTypesAndQos) {
  Peer peer(domain_);
  // The experiment's geometry (firmware_config/experiments/vergence_sphere.yaml): the dominant
  // left eye on the sphere at atan2(0.08, 0.96); the right eye verged on the point its central
  // ray meets, (0.900, 0.132) m, seen from (0.04, -0.06) m at atan2(0.192, 0.860).
  const double left_truth_deg = std::atan2(0.08, 0.96) * kDegPerRad;
  const double right_truth_deg = std::atan2(0.192, 0.860) * kDegPerRad;
  auto run = std::async(std::launch::async, [&] {
    return testing::run_cambio("run firmware_config/experiments/vergence_sphere.yaml --out '" +
                               out_.string() +
                               "' --set experiment.ros2.domain_id=" + std::to_string(domain_) +
                               " --set experiment.ros2.joint_states_hz=100");
  });
  while (run.wait_for(std::chrono::milliseconds(20)) != std::future_status::ready) peer.take();
  const testing::CommandResult result = run.get();
  ASSERT_EQ(result.exit_code, 0) << result.output;
  // The writer lingers for its reliable readers; the last samples may still be on the way.
  for (int i = 0; i < 50; ++i) {
    peer.take();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }

  ASSERT_TRUE(peer.publications.contains("rt/joint_states"));
  const Publication& joints = peer.publications.at("rt/joint_states");
  EXPECT_EQ(joints.type_name, "sensor_msgs::msg::dds_::JointState_");
  EXPECT_EQ(joints.reliability, DDS_RELIABILITY_RELIABLE);
  EXPECT_EQ(joints.history, DDS_HISTORY_KEEP_LAST);
  EXPECT_EQ(joints.depth, 10);
  ASSERT_TRUE(peer.publications.contains("rt/clock"));
  EXPECT_EQ(peer.publications.at("rt/clock").type_name, "rosgraph_msgs::msg::dds_::Clock_");
  // ROS 2's graph (what `ros2 node list` reads): the node /cambio, on the participant that DDS
  // discovery says writes /joint_states, listing that writer's GUID among its writers.
  ASSERT_FALSE(peer.graph_nodes.empty());
  const Peer::GraphNode& node = peer.graph_nodes.back();
  EXPECT_EQ(node.node_namespace, "/");
  EXPECT_EQ(node.name, "cambio");
  EXPECT_EQ(node.participant, joints.participant_key);
  EXPECT_NE(std::find(node.writers.begin(), node.writers.end(), joints.key), node.writers.end());
  EXPECT_NE(
      std::find(node.writers.begin(), node.writers.end(), peer.publications.at("rt/clock").key),
      node.writers.end());
  EXPECT_TRUE(node.readers.empty());  // This run takes no commands.

  // A 2 s run at 100 Hz of wall time publishes far more than this whatever the machine's load.
  ASSERT_GE(peer.joint_states.size(), 10u);
  const std::vector<std::string> head = {"neck_pan", "neck_tilt", "eye_tilt", "left_eye_pan",
                                         "right_eye_pan"};
  double previous_stamp_s = -1.0;
  for (const ReceivedJointState& m : peer.joint_states) {
    ASSERT_EQ(m.names.size(), 15u);
    EXPECT_TRUE(std::equal(head.begin(), head.end(), m.names.begin()));
    EXPECT_EQ(m.position_rad.size(), m.names.size());
    EXPECT_EQ(m.velocities, m.names.size());
    EXPECT_EQ(m.efforts, m.names.size());
    EXPECT_GT(m.stamp_s, previous_stamp_s) << "stamps go forward";
    previous_stamp_s = m.stamp_s;
  }
  // Simulated time: the last state is the run's end (2 s), and /clock says the same.
  const ReceivedJointState& last = peer.joint_states.back();
  EXPECT_NEAR(last.stamp_s, 2.0, 0.01);
  ASSERT_FALSE(peer.clock_s.empty());
  EXPECT_NEAR(peer.clock_s.back(), last.stamp_s, 1e-9);
  EXPECT_NEAR(last.position_rad[3] * kDegPerRad, left_truth_deg, 0.1);
  EXPECT_NEAR(last.position_rad[4] * kDegPerRad, right_truth_deg, 0.2);

  // The rig's tree: every joint's link on /tf with each joint state, the cameras' optical frames
  // once on /tf_static, kept for late joiners.
  ASSERT_TRUE(peer.publications.contains("rt/tf"));
  EXPECT_EQ(peer.publications.at("rt/tf").type_name, "tf2_msgs::msg::dds_::TFMessage_");
  EXPECT_EQ(peer.publications.at("rt/tf").depth, 100);
  ASSERT_TRUE(peer.publications.contains("rt/tf_static"));
  EXPECT_EQ(peer.publications.at("rt/tf_static").durability, DDS_DURABILITY_TRANSIENT_LOCAL);
  EXPECT_EQ(peer.publications.at("rt/tf_static").depth, 1);
  ASSERT_EQ(peer.tf_static.size(), 1u);
  ASSERT_TRUE(peer.tf_static[0].contains("left_eye_optical_frame"));
  const ReceivedTransform& optical = peer.tf_static[0].at("left_eye_optical_frame");
  EXPECT_EQ(optical.parent, "left_eye_pan");
  // ROS's optical convention: z forward (the link's x), x right (the link's -y), y down (-z).
  EXPECT_TRUE(optical.X_PC.linear().col(2).isApprox(Eigen::Vector3d::UnitX(), 1e-9));
  EXPECT_TRUE(optical.X_PC.linear().col(0).isApprox(-Eigen::Vector3d::UnitY(), 1e-9));
  // The robot for RViz: the URDF `cambio export urdf` writes, kept for late joiners.
  ASSERT_TRUE(peer.publications.contains("rt/robot_description"));
  EXPECT_EQ(peer.publications.at("rt/robot_description").durability,
            DDS_DURABILITY_TRANSIENT_LOCAL);
  EXPECT_EQ(peer.robot_description,
            testing::run_cambio("export urdf cambio", testing::Capture::kStdout).output);
  ASSERT_FALSE(peer.tf.empty());
  const ReceivedTf& tf = peer.tf.back();
  ASSERT_EQ(tf.size(), 15u);
  EXPECT_NEAR(tf.at("right_eye_pan").stamp_s, last.stamp_s, 1e-9);
  // The head's chain written out from the rig file (rigs/cambio.yaml: each joint's origin and
  // axis) at the last joint state's positions; the eyes' pan axes sit near (0.04, +-0.06, 1.40) m,
  // the experiment's geometry, the neck barely moved.
  const std::vector<double>& q = last.position_rad;
  auto eye_in_base = [&q](double y_m, double pan_rad) {
    using T = Eigen::Translation3d;
    using R = Eigen::AngleAxisd;
    const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d y = Eigen::Vector3d::UnitY();
    return Eigen::Isometry3d(T(0, 0, 1.20) * R(q[0], z) * T(0, 0, 0.10) * R(q[1], y) *
                             T(0.04, 0, 0.10) * R(q[2], y) * T(0, y_m, 0) * R(pan_rad, z));
  };
  const Eigen::Isometry3d X_BL = pose_in(tf, "base", "left_eye_pan");
  const Eigen::Isometry3d X_BR = pose_in(tf, "base", "right_eye_pan");
  EXPECT_TRUE(X_BL.isApprox(eye_in_base(0.06, q[3]), 1e-9)) << X_BL.matrix();
  EXPECT_TRUE(X_BR.isApprox(eye_in_base(-0.06, q[4]), 1e-9)) << X_BR.matrix();
  EXPECT_LT((X_BL.translation() - Eigen::Vector3d(0.04, 0.06, 1.40)).norm(), 0.002);

  // The left eye's images, as the rig describes them (rigs/cambio.yaml: 640x480 rgb8, f = 554.256
  // px, principal point at the centre, (w - 1) / 2 and (h - 1) / 2), best effort, in its optical
  // frame, stamped on the run's clock, and not blank (the sphere before a textured backdrop).
  ASSERT_TRUE(peer.publications.contains("rt/left_eye/image_raw"));
  const Publication& images = peer.publications.at("rt/left_eye/image_raw");
  EXPECT_EQ(images.type_name, "sensor_msgs::msg::dds_::Image_");
  EXPECT_EQ(images.reliability, DDS_RELIABILITY_BEST_EFFORT);
  EXPECT_EQ(images.depth, 5);
  ASSERT_FALSE(peer.images.empty());
  for (const ReceivedImage& image : peer.images) {
    EXPECT_EQ(image.frame_id, "left_eye_optical_frame");
    EXPECT_EQ(image.encoding, "rgb8");
    EXPECT_EQ(image.width, 640u);
    EXPECT_EQ(image.height, 480u);
    EXPECT_EQ(image.step, 640u * 3u);
    EXPECT_EQ(image.bytes, 640u * 480u * 3u);
    EXPECT_GT(image.level_spread, 50.0);
    EXPECT_GE(image.stamp_s, 0.0);
    EXPECT_LE(image.stamp_s, 2.0);
  }
  ASSERT_FALSE(peer.camera_infos.empty());
  const ReceivedCameraInfo& info = peer.camera_infos.back();
  EXPECT_EQ(info.frame_id, "left_eye_optical_frame");
  EXPECT_EQ(info.distortion_model, "plumb_bob");
  EXPECT_EQ(info.distortion_count, 5u);
  const std::array<double, 9> k = {554.256, 0, 319.5, 0, 554.256, 239.5, 0, 0, 1};
  const std::array<double, 12> projection = {554.256, 0, 319.5, 0, 0, 554.256,
                                             239.5,   0, 0,     0, 1, 0};
  EXPECT_EQ(info.k, k);
  EXPECT_EQ(info.p, projection);

  // /diagnostics (1 Hz of wall time, and once more at the end; the first, at start, may go out
  // before the peer is matched): every loop at its rate, each of the 15 drives operation
  // enabled, the joint loop driving.
  ASSERT_TRUE(peer.publications.contains("rt/diagnostics"));
  EXPECT_EQ(peer.publications.at("rt/diagnostics").type_name,
            "diagnostic_msgs::msg::dds_::DiagnosticArray_");
  ASSERT_FALSE(peer.diagnostics.empty());
  std::map<std::string, ReceivedStatus> by_name;
  for (const ReceivedStatus& status : peer.diagnostics.back()) by_name[status.name] = status;
  int drives = 0;
  for (const auto& [name, status] : by_name) {
    if (name.rfind("cambio: drive ", 0) != 0) continue;
    ++drives;
    EXPECT_EQ(status.values.at("drive_state"), "operation enabled") << name;
    EXPECT_EQ(status.values.at("error_code"), "0x0000") << name;
    EXPECT_EQ(status.level, 0) << name;
  }
  EXPECT_EQ(drives, 15);
  ASSERT_TRUE(by_name.contains("cambio: drive left_eye_pan"));
  EXPECT_NEAR(
      std::stod(by_name.at("cambio: drive left_eye_pan").values.at("position_rad")) * kDegPerRad,
      left_truth_deg, 0.1);
  ASSERT_TRUE(by_name.contains("cambio: joint loop joint holds"));
  EXPECT_EQ(by_name.at("cambio: joint loop joint holds").values.at("fault_latched"), "false");
  ASSERT_TRUE(by_name.contains("cambio: loop joint"));
  const ReceivedStatus& joint_loop = by_name.at("cambio: loop joint");
  EXPECT_EQ(std::stod(joint_loop.values.at("scheduled_rate_hz")), 400.0);  // rigs/cambio.yaml
  // Simulated time: the rate in run time is the schedule's (one cycle more or less per window
  // of at least 0.2 s).
  EXPECT_NEAR(std::stod(joint_loop.values.at("rate_hz")), 400.0, 5.5) << joint_loop.message;
  EXPECT_GE(std::stoull(joint_loop.values.at("cycles")), 799u);
  EXPECT_TRUE(by_name.contains("cambio: loop camera"));

  // The gaze: where the robot believes it looks, on the sphere's near surface (the scene's
  // geometry), in base; its status says it fixates with a confident disparity near zero.
  ASSERT_FALSE(peer.fixations.empty());
  EXPECT_EQ(peer.fixation_frames.back(), "base");
  const Eigen::Vector3d sphere_m(1.0, 0.14, 1.40);
  EXPECT_NEAR((peer.fixations.back() - sphere_m).norm(), 0.10, 0.03) << peer.fixations.back();
  // The closed form: the point the left eye's central ray meets, (0.900, 0.132, 1.40) m (above).
  EXPECT_LT((peer.fixations.back() - Eigen::Vector3d(0.900, 0.132, 1.40)).norm(), 0.005)
      << peer.fixations.back();
  ASSERT_FALSE(peer.gaze_status.empty());
  const ReceivedStatus& gaze = peer.gaze_status.back();
  EXPECT_EQ(gaze.name, "cambio: gaze");
  EXPECT_EQ(gaze.values.at("action"), "fixate");
  EXPECT_EQ(gaze.values.at("disparity_valid"), "true");
  EXPECT_LT(std::abs(std::stod(gaze.values.at("disparity_px"))), 2.0);
  std::printf(
      "/diagnostics: %zu arrays of %zu statuses; loop joint: %s; /cambio/gaze/status: %s, "
      "disparity %s px at confidence %s; fixation (%.3f, %.3f, %.3f) m\n",
      peer.diagnostics.size(), peer.diagnostics.back().size(), joint_loop.message.c_str(),
      gaze.message.c_str(), gaze.values.at("disparity_px").c_str(),
      gaze.values.at("disparity_confidence").c_str(), peer.fixations.back().x(),
      peer.fixations.back().y(), peer.fixations.back().z());
}

TEST_F(Ros2Wire, ALookAtFromAPeerTurnsTheEyesAndBadOnesAreRefusedWithTheirReasons) {
  Peer peer(domain_);
  // Both eyes start straight ahead; the run has no gaze commands of its own (ROS 2's are its
  // commands). On the wall clock, so that the peer has time to be heard.
  const double left_truth_deg = std::atan2(0.08, 0.96) * kDegPerRad;
  const std::filesystem::path experiment = write_commanded_experiment("look_at");
  auto run = std::async(std::launch::async, [&] {
    return testing::run_cambio("run '" + experiment.string() + "' --out '" +
                               (out_ / "out").string() + "'");
  });
  while (run.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
    peer.take();
    if (peer.joint_states.empty()) continue;  // Not heard from the run yet.
    peer.look_at("nowhere", 1.0, 0.0, 1.4);
    peer.look_at("base", std::nan(""), 0.0, 1.4);
    peer.look_at("base", 1.0, 0.14, 1.40);  // The sphere's centre.
  }
  const testing::CommandResult result = run.get();
  ASSERT_EQ(result.exit_code, 0) << result.output;
  peer.drain();
  ASSERT_FALSE(peer.joint_states.empty());
  EXPECT_NEAR(peer.joint_states.back().position_rad[3] * kDegPerRad, left_truth_deg, 0.3);
  const auto refused = [&](const std::string& what) {
    return std::any_of(peer.refusals.begin(), peer.refusals.end(),
                       [&](const std::string& r) { return r.find(what) != std::string::npos; });
  };
  EXPECT_TRUE(refused("frame 'nowhere' is not in this robot's tf tree"));
  EXPECT_TRUE(refused("is not finite"));
  EXPECT_FALSE(refused("(1, 0.14, 1.4)")) << "the good target was refused";
  EXPECT_NE(result.output.find("ROS 2 command refused"), std::string::npos) << "and logged";
}

// The console's lines from a ROS 2 node (/cambio/command): one that acts on the robot is carried
// out with the console's checks; one about the console's own session, a misspelt one, one naming
// no joint and an endless one are refused with their reasons on /cambio/refusals.
TEST_F(Ros2Wire, ConsoleLinesFromAPeerMoveTheRobotAndBadOnesAreRefusedWithTheirReasons) {
  Peer peer(domain_);
  const std::filesystem::path experiment = write_commanded_experiment("command");
  auto run = std::async(std::launch::async, [&] {
    return testing::run_cambio("run '" + experiment.string() + "' --out '" +
                               (out_ / "out").string() + "'");
  });
  const std::string endless(5000, 'x');
  while (run.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
    peer.take();
    if (peer.joint_states.empty() || peer.refused("longer than")) continue;
    // Until the run has heard them (the first writes may precede the match).
    peer.command("move left_eye_pan 5deg");
    peer.command("wait 1");
    peer.command("sacade point 1 0.14 1.4");
    peer.command("move elbow 1");
    peer.command(endless);
  }
  const testing::CommandResult result = run.get();
  ASSERT_EQ(result.exit_code, 0) << result.output;
  peer.drain();
  ASSERT_FALSE(peer.joint_states.empty());
  EXPECT_NEAR(peer.joint_states.back().position_rad[3] * kDegPerRad, 5.0, 0.3);
  EXPECT_TRUE(peer.refused("/cambio/command: 'wait' is for the console's own session"));
  EXPECT_TRUE(peer.refused("did you mean \"saccade\"?"));
  EXPECT_TRUE(peer.refused("no joint \"elbow\""));
  EXPECT_TRUE(peer.refused("/cambio/command: a line longer than 1000 bytes"));
  EXPECT_FALSE(peer.refused("left_eye_pan")) << "the good line was refused";
  for (const std::string& refusal : peer.refusals) std::printf("refused: %s\n", refusal.c_str());
}

// Joint trajectories from a ROS 2 node (/cambio/joint_trajectory): one for the head (a spline
// through positions and velocities) and one for an arm (positions only) are followed to their last
// points; a NaN, a million points, an unknown joint, head and arm joints together, times that do
// not increase and a first point too far to reach in its time are each refused with the reason.
TEST_F(Ros2Wire, JointTrajectoriesFromAPeerMoveTheHeadAndArmAndBadOnesAreRefused) {
  Peer peer(domain_);
  const std::filesystem::path experiment = write_commanded_experiment("trajectory");
  auto run = std::async(std::launch::async, [&] {
    return testing::run_cambio("run '" + experiment.string() + "' --out '" +
                               (out_ / "out").string() + "'");
  });
  bool sent = false;
  double elbow0_rad = 0.0;
  while (run.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
    peer.take();
    if (peer.joint_states.empty() || sent) continue;
    if (!peer.refused("no joint \"neck_yaw\"")) {
      // Until the run has heard one (the first writes may precede the match).
      peer.trajectory({"neck_yaw"}, {{1.0, 0.1}});
      continue;
    }
    sent = true;
    elbow0_rad = peer.position_rad("left_elbow");
    peer.trajectory({"neck_pan"}, {{1.0, std::nan("")}});
    peer.trajectory({"neck_pan", "left_elbow"}, {{1.0, 0.1, 0.1}});
    peer.trajectory({"neck_pan"}, {{1.0, 0.1}, {1.0, 0.2}});
    peer.trajectory({"neck_pan"}, {{0.01, 0.5}});
    peer.trajectory({"neck_pan"}, {{1.0, 0.1, 0.2}});
    // Rest to 0.2 rad at rest by 1 s, then to 0.1 rad by 2 s.
    peer.trajectory({"neck_pan"}, {{1.0, 0.2}, {2.0, 0.1}}, {{0.0}, {0.0}});
    peer.trajectory({"left_elbow"}, {{1.5, elbow0_rad + 0.2}});
    peer.trajectory({"neck_pan"}, std::vector<std::vector<double>>(1'000'000, {1.0, 0.1}));
  }
  const testing::CommandResult result = run.get();
  ASSERT_EQ(result.exit_code, 0) << result.output;
  peer.drain();
  ASSERT_TRUE(sent);
  for (const std::string& refusal : peer.refusals) std::printf("refused: %s\n", refusal.c_str());
  EXPECT_TRUE(peer.refused("joint neck_pan, point 0 (1 s): position nan rad is not within"));
  EXPECT_TRUE(peer.refused("1000000 points; a trajectory has 1 to 128"));
  EXPECT_TRUE(peer.refused("the head's joints or the arms', not both"));
  EXPECT_TRUE(peer.refused("point 1 (1 s): not after point 0 (1 s) (times must increase)"));
  EXPECT_TRUE(peer.refused("joint neck_pan: from where it is to point 0 (0.01 s): 50 rad/s"));
  EXPECT_TRUE(peer.refused("point 0 has 2 positions for 1 joints"));
  // The head followed its spline (never beyond its extremes) and holds the last point; the
  // arm its line.
  double peak_rad = 0.0;
  for (const ReceivedJointState& state : peer.joint_states) {
    const auto it = std::find(state.names.begin(), state.names.end(), "neck_pan");
    ASSERT_NE(it, state.names.end());
    peak_rad =
        std::max(peak_rad, state.position_rad[static_cast<std::size_t>(it - state.names.begin())]);
  }
  EXPECT_NEAR(peak_rad, 0.2, 0.01);
  EXPECT_NEAR(peer.position_rad("neck_pan"), 0.1, 0.005);
  EXPECT_NEAR(peer.position_rad("left_elbow"), elbow0_rad + 0.2, 0.005);
  std::printf("trajectory: neck_pan peak %.4f rad, final %.4f rad; left_elbow %.4f -> %.4f rad\n",
              peak_rad, peer.position_rad("neck_pan"), elbow0_rad, peer.position_rad("left_elbow"));
}

// A node that floods /cambio/look_at (20,000 targets in a burst, four times): the bridge's reader
// keeps the newest 10 (the rest is dropped by DDS, never queued), the run counts what it took;
// /joint_states keeps its rate through it and the eyes end on the target.
TEST_F(Ros2Wire, AFloodOfCommandsIsDroppedAndCountedWhileTheRunGoesOn) {
  Peer peer(domain_);
  const std::filesystem::path experiment = write_commanded_experiment("flood");
  auto run = std::async(std::launch::async, [&] {
    return testing::run_cambio("run '" + experiment.string() + "' --out '" +
                               (out_ / "out").string() + "'");
  });
  int sent = 0;
  int bursts = 0;
  while (run.wait_for(std::chrono::milliseconds(100)) != std::future_status::ready) {
    peer.take();
    if (peer.joint_states.empty() || bursts == 4) continue;
    sent += peer.flood_look_at(20'000, 1.0, 0.14, 1.40);  // The sphere's centre.
    ++bursts;
  }
  const testing::CommandResult result = run.get();
  ASSERT_EQ(result.exit_code, 0) << result.output;
  peer.take();
  ASSERT_EQ(bursts, 4);
  std::ifstream summary_file(out_ / "out" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  const auto taken = summary.at("ros2").at("commands_received").get<std::uint64_t>();
  std::printf("flood: %d look-ats sent, %llu taken\n", sent,
              static_cast<unsigned long long>(taken));
  EXPECT_GT(taken, 0u);
  EXPECT_LE(taken, static_cast<std::uint64_t>(sent));
  EXPECT_EQ(summary.at("ros2").at("commands_refused").get<std::uint64_t>(), 0u) << result.output;
  // The joint states kept coming at 50 Hz of wall time: no gap of a quarter second in run time.
  ASSERT_GE(peer.joint_states.size(), 50u);
  double widest_gap_s = 0.0;
  for (std::size_t i = 1; i < peer.joint_states.size(); ++i) {
    widest_gap_s =
        std::max(widest_gap_s, peer.joint_states[i].stamp_s - peer.joint_states[i - 1].stamp_s);
  }
  std::printf("flood: %zu joint states received, widest gap %.3f s\n", peer.joint_states.size(),
              widest_gap_s);
  EXPECT_LT(widest_gap_s, 0.25);
  EXPECT_NEAR(peer.joint_states.back().position_rad[3] * kDegPerRad,
              std::atan2(0.08, 0.96) * kDegPerRad, 0.3);
}

}  // namespace
}  // namespace cambio
