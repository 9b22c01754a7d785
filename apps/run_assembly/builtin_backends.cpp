#include "builtin_backends.hpp"

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cambio/can/can_traffic_log.hpp"
#include "cambio/can/socketcan_bus.hpp"
#include "cambio/canopen/can_rig_from_config.hpp"
#include "cambio/canopen/socketcan_backend.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "cambio/v4l2/v4l2_backend.hpp"
#include "cambio/v4l2/v4l2_rig_from_config.hpp"

namespace cambio::app {
namespace {

/// Receive filters passing every frame of the predefined connection set from or to the nodes
/// driven on `bus` (TPDOs, SDO answers, EMCY, heartbeats; id & 0x7F == node), plus NMT and SYNC.
std::vector<can::CanFilter> node_filters(const hal::HardwareInfo& hardware,
                                         const canopen::CanRigInfo& can_rig,
                                         const canopen::CanBusInfo& bus) {
  std::vector<can::CanFilter> filters;
  for (const auto& group : hardware.groups) {
    const canopen::CanGroupInfo* can_group = can_rig.find_group(group.name);
    if (group.backend != canopen::SocketCanBackend::kName || can_group == nullptr ||
        can_group->bus != bus.name) {
      continue;
    }
    for (const auto& joint_name : group.joints) {
      const canopen::JointDriveInfo* drive = can_rig.find_drive(joint_name);
      if (drive == nullptr) continue;
      filters.push_back({static_cast<std::uint32_t>(drive->node_id), 0x7Fu});
    }
  }
  return filters;
}

}  // namespace

void register_builtin_backends(hal::BackendFactory& factory,
                               const config::ExperimentConfig& experiment,
                               can::CanTrafficLog* can_log) {
  // The experiment's own copy of its scene (with its `scene.` overrides), so the sim's world and
  // the experiment's object targets cannot disagree.
  config::SceneConfig scene;
  if (experiment.scene) {
    scene = *experiment.scene;
  } else if (!experiment.scene_path.empty()) {
    scene = config::load_scene(config::resolve_config_argument("scenes", experiment.scene_path));
  } else {
    scene.name = "empty";
  }
  sim::register_sim_backend(factory, experiment.rig, std::move(scene));
  v4l2::register_v4l2_backend(factory, v4l2::v4l2_rig_from_config(experiment.rig));

  canopen::SocketCanBackendOptions options;
  if (const config::LoopConfig* joint_loop = experiment.rig.find_loop("joint")) {
    options.default_joint_rate_hz = joint_loop->rate_hz;
  }
  const hal::HardwareInfo hardware = config::hardware_description(experiment.rig);
  canopen::CanRigInfo can_rig = canopen::can_rig_from_config(experiment.rig);
  std::map<std::string, std::vector<can::CanFilter>, std::less<>> filters;
  for (const auto& bus : can_rig.buses) filters[bus.name] = node_filters(hardware, can_rig, bus);
  canopen::register_socketcan_backend(
      factory, std::move(can_rig),
      [can_log, filters](const canopen::CanBusInfo& info) -> std::unique_ptr<hal::CanBus> {
        can::SocketCanOptions bus_options;
        bus_options.interface = info.interface;
        bus_options.fd = info.fd;
        if (const auto it = filters.find(info.name); it != filters.end()) {
          bus_options.filters = it->second;
        }
        std::unique_ptr<hal::CanBus> bus = can::SocketCanBus::open(bus_options);
        if (can_log == nullptr) return bus;
        return std::make_unique<can::LoggingCanBus>(std::move(bus), *can_log);
      },
      options);
}

}  // namespace cambio::app
