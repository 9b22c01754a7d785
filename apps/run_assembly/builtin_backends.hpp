#pragma once

#include "cambio/config/experiment_config.hpp"
#include "cambio/hal/backend_factory.hpp"

namespace cambio::can {
class CanTrafficLog;
}

namespace cambio::app {

/// Registers every backend this build of `cambio` carries, with what only that backend needs
/// taken from the experiment (the sim: the rig file's world description and the scene), and
/// "socketcan" opens each bus the rig names on its kernel interface (SocketCAN), receiving only
/// the frames of the node ids driven there; with `can_log` every frame sent and received on
/// those buses is logged (`candump -L` format); "v4l2" opens each of its cameras' device nodes.
/// Throws config::ConfigError for a bad scene file.
void register_builtin_backends(hal::BackendFactory& factory,
                               const config::ExperimentConfig& experiment,
                               can::CanTrafficLog* can_log = nullptr);

}  // namespace cambio::app
