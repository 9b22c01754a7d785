#pragma once

#include <dds/dds.h>

#include <string>
#include <vector>

// ROS 2's graph: how `ros2 node list` and `ros2 topic info` learn which node owns which readers
// and writers. Internal to cambio_ros2.

namespace cambio::ros2 {

/// Announces node `/node_name` on ros_discovery_info (rmw_dds_common/ParticipantEntitiesInfo,
/// reliable transient-local keep-last 1, no "rt/": rmw_cyclonedds' own graph topic) with its
/// participant's and endpoints' GIDs (entities <= 0 are skipped). Once: they never change.
/// Returns the writer; false from `written` when the write failed.
dds_entity_t announce_node(dds_entity_t participant, const std::string& node_name,
                           const std::vector<dds_entity_t>& writers,
                           const std::vector<dds_entity_t>& readers, bool& written);

}  // namespace cambio::ros2
