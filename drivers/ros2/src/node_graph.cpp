#include "node_graph.hpp"

#include <cstdio>
#include <cstring>

#include "dds_entities.hpp"
#include "rmw_dds_common/msg/ParticipantEntitiesInfo.h"

namespace cambio::ros2 {
namespace {

// A GID is the entity's DDS GUID, zero-padded (rmw_cyclonedds' convert_guid_to_gid): what a
// peer's graph cache sees of the same entities through DDS's own discovery.
rmw_dds_common_msg_dds__Gid_ gid_of(dds_entity_t entity) {
  rmw_dds_common_msg_dds__Gid_ gid{};
  dds_guid_t guid{};
  if (entity > 0 && dds_get_guid(entity, &guid) == DDS_RETCODE_OK) {
    static_assert(sizeof(guid.v) <= sizeof(gid.data));
    std::memcpy(gid.data, guid.v, sizeof(guid.v));
  }
  return gid;
}

std::vector<rmw_dds_common_msg_dds__Gid_> gids_of(const std::vector<dds_entity_t>& entities) {
  std::vector<rmw_dds_common_msg_dds__Gid_> gids;
  for (const dds_entity_t entity : entities) {
    if (entity > 0) gids.push_back(gid_of(entity));
  }
  return gids;
}

}  // namespace

dds_entity_t announce_node(dds_entity_t participant, const std::string& node_name,
                           const std::vector<dds_entity_t>& writers,
                           const std::vector<dds_entity_t>& readers, bool& written) {
  // rmw_cyclonedds' graph topic: its name has no "rt/" and its QoS keeps the newest for late
  // joiners (rmw_context_impl_s::init).
  const dds::Qos graph(DDS_RELIABILITY_RELIABLE, 1, DDS_DURABILITY_TRANSIENT_LOCAL);
  const std::string what = "create the writer of ros_discovery_info";
  const dds_entity_t writer = dds::checked(
      dds_create_writer(
          participant,
          dds::checked(
              dds_create_topic(participant, &rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc,
                               "ros_discovery_info", graph.qos, nullptr),
              what),
          graph.qos, nullptr),
      what);
  std::vector<rmw_dds_common_msg_dds__Gid_> writer_gids = gids_of(writers);
  std::vector<rmw_dds_common_msg_dds__Gid_> reader_gids = gids_of(readers);
  rmw_dds_common_msg_dds__NodeEntitiesInfo_ node{};
  std::snprintf(node.node_namespace, sizeof(node.node_namespace), "/");
  std::snprintf(node.node_name, sizeof(node.node_name), "%s", node_name.c_str());
  const auto readers_n = static_cast<std::uint32_t>(reader_gids.size());
  const auto writers_n = static_cast<std::uint32_t>(writer_gids.size());
  node.reader_gid_seq = {readers_n, readers_n, reader_gids.data(), false};
  node.writer_gid_seq = {writers_n, writers_n, writer_gids.data(), false};
  rmw_dds_common_msg_dds__ParticipantEntitiesInfo_ info{};
  info.gid = gid_of(participant);
  info.node_entities_info_seq = {1, 1, &node, false};
  written = dds_write(writer, &info) == DDS_RETCODE_OK;
  return writer;
}

}  // namespace cambio::ros2
