#include "cambio/ros2/ros2_bridge.hpp"

#include <dds/dds.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "cambio/ros2/ros_time.hpp"
#include "rosgraph_msgs/msg/Clock.h"
#include "sensor_msgs/msg/JointState.h"

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

// QoS as ROS 2 uses it for state and commands: reliable, keep last 10, volatile.
struct StateQos {
  StateQos() : qos(dds_create_qos()) {
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 10);
    dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
  }
  ~StateQos() { dds_delete_qos(qos); }
  StateQos(const StateQos&) = delete;
  StateQos& operator=(const StateQos&) = delete;
  dds_qos_t* qos;
};

}  // namespace

// The participant and its writers; deleting the participant deletes them (writers linger for
// reliable readers' acknowledgements, Cyclone's WriterLingerDuration).
struct Ros2Bridge::Dds {
  dds_entity_t participant = 0;
  dds_entity_t joint_states = 0;
  dds_entity_t clock = 0;
  std::vector<char*> names;  // Into the bridge's joint_names_; the message borrows them.
  ~Dds() {
    if (participant > 0) dds_delete(participant);
  }
};

Ros2Bridge::Ros2Bridge(const BridgeSettings& settings, std::vector<std::string> joint_names,
                       JointStatesSampler sampler)
    : settings_(settings), joint_names_(std::move(joint_names)), sampler_(std::move(sampler)) {
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
  const StateQos qos;
  if (settings_.joint_states_rate_hz > 0.0) {
    const dds_entity_t topic =
        checked(dds_create_topic(dds_->participant, &sensor_msgs_msg_dds__JointState__desc,
                                 "rt/joint_states", qos.qos, nullptr),
                "create topic /joint_states");
    dds_->joint_states = checked(dds_create_writer(dds_->participant, topic, qos.qos, nullptr),
                                 "create the /joint_states writer");
    if (settings_.publish_clock) {
      const dds_entity_t clock_topic =
          checked(dds_create_topic(dds_->participant, &rosgraph_msgs_msg_dds__Clock__desc,
                                   "rt/clock", qos.qos, nullptr),
                  "create topic /clock");
      dds_->clock = checked(dds_create_writer(dds_->participant, clock_topic, qos.qos, nullptr),
                            "create the /clock writer");
    }
  }
  for (std::string& name : joint_names_) dds_->names.push_back(name.data());
}

Ros2Bridge::~Ros2Bridge() {
  stop();
}

void Ros2Bridge::start() {
  if (thread_.joinable() || dds_->joint_states == 0) return;
  thread_ = std::thread([this] { publish_loop(); });
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
  return {joint_states_sent_.load(), clock_sent_.load(), write_errors_.load()};
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
}

}  // namespace cambio::ros2
