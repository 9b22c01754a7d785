#include "cambio/ros2/ros2_bridge.hpp"

#include <dds/dds.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "cambio/ros2/ros_time.hpp"
#include "rosgraph_msgs/msg/Clock.h"
#include "sensor_msgs/msg/JointState.h"
#include "tf2_msgs/msg/TFMessage.h"

namespace cambio::ros2 {
namespace {

// More joints than any robot this stack drives; a bound keeps a message's size known.
constexpr std::size_t kMaxJoints = 256;
constexpr double kMaxRateHz = 1000.0;

std::string dds_error(const char* what, dds_return_t code) {
  return std::string("ROS 2 bridge: cannot ") + what + ": " + dds_strretcode(code);
}

dds_entity_t checked(dds_entity_t entity, const char* what) {
  if (entity < 0) throw std::runtime_error(dds_error(what, entity));
  return entity;
}

// Reliable QoS as ROS 2 uses it: keep last 10 volatile for state and commands, keep last 100
// for /tf, keep last 1 transient-local for /tf_static (late joiners get it).
struct ReliableQos {
  explicit ReliableQos(std::int32_t depth,
                       dds_durability_kind_t durability = DDS_DURABILITY_VOLATILE)
      : qos(dds_create_qos()) {
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, depth);
    dds_qset_durability(qos, durability);
  }
  ~ReliableQos() { dds_delete_qos(qos); }
  ReliableQos(const ReliableQos&) = delete;
  ReliableQos& operator=(const ReliableQos&) = delete;
  dds_qos_t* qos;
};

// A topic and its writer under ROS 2's name for `ros_topic` (rmw_cyclonedds: "rt" + the name).
dds_entity_t make_writer(dds_entity_t participant, const dds_topic_descriptor_t& type,
                         const std::string& ros_topic, const ReliableQos& qos) {
  const std::string what = "create the writer of " + ros_topic;
  const dds_entity_t topic =
      checked(dds_create_topic(participant, &type, ("rt" + ros_topic).c_str(), qos.qos, nullptr),
              what.c_str());
  return checked(dds_create_writer(participant, topic, qos.qos, nullptr), what.c_str());
}

void set_transform(geometry_msgs_msg_dds__Transform_& out, const FrameTransform& in) {
  out.translation = {in.translation_m[0], in.translation_m[1], in.translation_m[2]};
  out.rotation = {in.rotation_xyzw[0], in.rotation_xyzw[1], in.rotation_xyzw[2],
                  in.rotation_xyzw[3]};
}

}  // namespace

// The participant and its writers; deleting the participant deletes them (writers linger for
// reliable readers' acknowledgements, Cyclone's WriterLingerDuration).
struct Ros2Bridge::Dds {
  dds_entity_t participant = 0;
  dds_entity_t joint_states = 0;
  dds_entity_t clock = 0;
  dds_entity_t tf = 0;
  dds_entity_t tf_static = 0;
  std::vector<char*> names;  // Into the bridge's joint_names_; the message borrows them.
  // One per joint, their frame names borrowed from the bridge's tf_tree_.
  std::vector<geometry_msgs_msg_dds__TransformStamped_> joint_transforms;
  ~Dds() {
    if (participant > 0) dds_delete(participant);
  }
};

Ros2Bridge::Ros2Bridge(const BridgeSettings& settings, std::vector<std::string> joint_names,
                       TfTree tf_tree, JointStatesSampler sampler)
    : settings_(settings),
      joint_names_(std::move(joint_names)),
      tf_tree_(std::move(tf_tree)),
      sampler_(std::move(sampler)) {
  if (joint_names_.size() > kMaxJoints) {
    throw std::invalid_argument("ROS 2 bridge: " + std::to_string(joint_names_.size()) +
                                " joints, at most " + std::to_string(kMaxJoints));
  }
  if (!(settings_.joint_states_rate_hz >= 0.0 && settings_.joint_states_rate_hz <= kMaxRateHz)) {
    throw std::invalid_argument("ROS 2 bridge: joint states rate " +
                                std::to_string(settings_.joint_states_rate_hz) +
                                " Hz, expected 0 to 1000");
  }
  const std::size_t n = joint_names_.size();
  sample_.position_rad.assign(n, 0.0);
  sample_.velocity_rad_s.assign(n, 0.0);
  sample_.effort_nm.assign(n, 0.0);

  dds_ = std::make_unique<Dds>();
  dds_->participant = checked(dds_create_participant(settings_.domain_id, nullptr, nullptr),
                              "join the DDS domain (check CYCLONEDDS_URI and the domain id)");
  for (const TfJoint& joint : tf_tree_.joints) {
    if (joint.position_index >= n) {
      throw std::invalid_argument("ROS 2 bridge: tf joint '" + joint.child_frame +
                                  "' has no position in the joint states");
    }
  }
  const ReliableQos state_qos(10);
  if (settings_.joint_states_rate_hz > 0.0) {
    dds_->joint_states = make_writer(dds_->participant, sensor_msgs_msg_dds__JointState__desc,
                                     "/joint_states", state_qos);
    if (settings_.publish_clock) {
      dds_->clock =
          make_writer(dds_->participant, rosgraph_msgs_msg_dds__Clock__desc, "/clock", state_qos);
    }
    if (settings_.publish_tf) {
      dds_->tf = make_writer(dds_->participant, tf2_msgs_msg_dds__TFMessage__desc, "/tf",
                             ReliableQos(100));
    }
  }
  if (settings_.publish_tf) {
    dds_->tf_static = make_writer(dds_->participant, tf2_msgs_msg_dds__TFMessage__desc,
                                  "/tf_static", ReliableQos(1, DDS_DURABILITY_TRANSIENT_LOCAL));
  }
  for (std::string& name : joint_names_) dds_->names.push_back(name.data());
  for (TfJoint& joint : tf_tree_.joints) {
    geometry_msgs_msg_dds__TransformStamped_ transform{};
    transform.header.frame_id = joint.parent_frame.data();
    transform.child_frame_id = joint.child_frame.data();
    dds_->joint_transforms.push_back(transform);
  }
}

Ros2Bridge::~Ros2Bridge() {
  stop();
}

void Ros2Bridge::start() {
  if (started_) return;
  started_ = true;
  if (dds_->tf_static != 0) publish_tf_static();
  if (dds_->joint_states != 0) thread_ = std::thread([this] { publish_loop(); });
}

void Ros2Bridge::stop() {
  if (!thread_.joinable()) return;
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

BridgeCounts Ros2Bridge::counts() const {
  return {joint_states_sent_.load(), clock_sent_.load(), tf_sent_.load(), write_errors_.load()};
}

void Ros2Bridge::publish_loop() {
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / settings_.joint_states_rate_hz));
  auto next = std::chrono::steady_clock::now();
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    lock.unlock();
    publish_newest();
    lock.lock();
    // A late wake-up skips the ticks it missed rather than publishing them in a burst.
    next = std::max(next + period, std::chrono::steady_clock::now());
    wake_.wait_until(lock, next, [this] { return stopping_; });
  }
  lock.unlock();
  publish_newest();  // The state the run ended in.
}

void Ros2Bridge::publish_newest() {
  if (!sampler_(sample_) || sample_.stamp_ns == last_published_stamp_ns_) return;
  last_published_stamp_ns_ = sample_.stamp_ns;
  const RosTime stamp = to_ros_time(sample_.stamp_ns, settings_.epoch_offset_ns);
  const auto n = static_cast<std::uint32_t>(joint_names_.size());
  auto sequence = [n](std::vector<double>& values) {
    return dds_sequence_double{n, n, values.data(), false};
  };
  sensor_msgs_msg_dds__JointState_ message{};
  message.header.stamp = {stamp.sec, stamp.nanosec};
  message.header.frame_id = const_cast<char*>("");  // Joint states name their joints, no frame.
  message.name = dds_sequence_string{n, n, dds_->names.data(), false};
  message.position = sequence(sample_.position_rad);
  message.velocity = sequence(sample_.velocity_rad_s);
  message.effort = sequence(sample_.effort_nm);
  if (dds_write(dds_->joint_states, &message) == DDS_RETCODE_OK) {
    joint_states_sent_.fetch_add(1, std::memory_order_relaxed);
  } else {
    write_errors_.fetch_add(1, std::memory_order_relaxed);
  }
  if (dds_->clock != 0) {
    const rosgraph_msgs_msg_dds__Clock_ clock{{stamp.sec, stamp.nanosec}};
    if (dds_write(dds_->clock, &clock) == DDS_RETCODE_OK) {
      clock_sent_.fetch_add(1, std::memory_order_relaxed);
    } else {
      write_errors_.fetch_add(1, std::memory_order_relaxed);
    }
  }
  if (dds_->tf != 0) publish_tf(sample_.stamp_ns);
}

void Ros2Bridge::publish_tf(std::int64_t stamp_ns) {
  const RosTime stamp = to_ros_time(stamp_ns, settings_.epoch_offset_ns);
  for (std::size_t k = 0; k < tf_tree_.joints.size(); ++k) {
    const TfJoint& joint = tf_tree_.joints[k];
    geometry_msgs_msg_dds__TransformStamped_& out = dds_->joint_transforms[k];
    out.header.stamp = {stamp.sec, stamp.nanosec};
    set_transform(out.transform,
                  joint_transform(joint, sample_.position_rad[joint.position_index]));
  }
  const auto n = static_cast<std::uint32_t>(dds_->joint_transforms.size());
  const tf2_msgs_msg_dds__TFMessage_ message{{n, n, dds_->joint_transforms.data(), false}};
  if (dds_write(dds_->tf, &message) == DDS_RETCODE_OK) {
    tf_sent_.fetch_add(1, std::memory_order_relaxed);
  } else {
    write_errors_.fetch_add(1, std::memory_order_relaxed);
  }
}

void Ros2Bridge::publish_tf_static() {
  // Fixed frames hold for all time; tf ignores a static transform's stamp.
  const RosTime stamp = to_ros_time(0, settings_.epoch_offset_ns);
  std::vector<geometry_msgs_msg_dds__TransformStamped_> transforms;
  for (TfFixed& fixed : tf_tree_.fixed) {
    geometry_msgs_msg_dds__TransformStamped_ transform{};
    transform.header.stamp = {stamp.sec, stamp.nanosec};
    transform.header.frame_id = fixed.parent_frame.data();
    transform.child_frame_id = fixed.child_frame.data();
    set_transform(transform.transform, to_frame_transform(fixed.X_PC));
    transforms.push_back(transform);
  }
  const auto n = static_cast<std::uint32_t>(transforms.size());
  const tf2_msgs_msg_dds__TFMessage_ message{{n, n, transforms.data(), false}};
  if (dds_write(dds_->tf_static, &message) == DDS_RETCODE_OK) {
    tf_sent_.fetch_add(1, std::memory_order_relaxed);
  } else {
    write_errors_.fetch_add(1, std::memory_order_relaxed);
  }
}

}  // namespace cambio::ros2
