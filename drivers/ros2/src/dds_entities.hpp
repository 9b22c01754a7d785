#pragma once

#include <dds/dds.h>

#include <cstdint>
#include <stdexcept>
#include <string>

// Cyclone DDS entities under the names and QoS ROS 2 gives them (rmw_cyclonedds), shared by the
// bridge and the perception link. Internal to cambio_ros2.

namespace cambio::ros2::dds {

/// Throws std::runtime_error "ROS 2: cannot <what>: <Cyclone's reason>" for a failed call.
inline dds_entity_t checked(dds_entity_t entity, const std::string& what) {
  if (entity < 0) {
    throw std::runtime_error("ROS 2: cannot " + what + ": " + dds_strretcode(entity));
  }
  return entity;
}

/// QoS as ROS 2 uses it: reliable keep-last 10 volatile for state and commands, keep-last 100
/// for /tf, keep-last 1 transient-local for latched topics (late joiners get them); best-effort
/// keep-last 5 for sensor data (rclcpp's SensorDataQoS).
struct Qos {
  Qos(dds_reliability_kind_t reliability, std::int32_t depth,
      dds_durability_kind_t durability = DDS_DURABILITY_VOLATILE)
      : qos(dds_create_qos()) {
    dds_qset_reliability(qos, reliability, DDS_MSECS(100));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, depth);
    dds_qset_durability(qos, durability);
  }
  ~Qos() { dds_delete_qos(qos); }
  Qos(const Qos&) = delete;
  Qos& operator=(const Qos&) = delete;
  dds_qos_t* qos;
};

/// The DDS topic of ROS topic `ros_topic` (rmw_cyclonedds: "rt" + the name).
inline dds_entity_t make_topic(dds_entity_t participant, const dds_topic_descriptor_t& type,
                               const std::string& ros_topic, const Qos& qos,
                               const std::string& what) {
  return checked(dds_create_topic(participant, &type, ("rt" + ros_topic).c_str(), qos.qos, nullptr),
                 what);
}

inline dds_entity_t make_writer(dds_entity_t participant, const dds_topic_descriptor_t& type,
                                const std::string& ros_topic, const Qos& qos) {
  const std::string what = "create the writer of " + ros_topic;
  return checked(dds_create_writer(participant, make_topic(participant, type, ros_topic, qos, what),
                                   qos.qos, nullptr),
                 what);
}

inline dds_entity_t make_reader(dds_entity_t participant, const dds_topic_descriptor_t& type,
                                const std::string& ros_topic, const Qos& qos) {
  const std::string what = "create the reader of " + ros_topic;
  return checked(dds_create_reader(participant, make_topic(participant, type, ros_topic, qos, what),
                                   qos.qos, nullptr),
                 what);
}

}  // namespace cambio::ros2::dds
