#include "builtin_backends.hpp"

#include "cambio/config/scene_config.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/sim/sim_backend.hpp"

namespace cambio::app {

void register_builtin_backends(hal::BackendFactory& factory,
                               const config::ExperimentConfig& experiment) {
  config::SceneConfig scene;
  if (!experiment.scene_path.empty()) {
    scene = config::load_scene(config::resolve_config_argument("scenes", experiment.scene_path));
  } else {
    scene.name = "empty";
  }
  sim::register_sim_backend(factory, experiment.rig, std::move(scene));
  factory.declare_unbuilt("socketcan", "its CANopen drivers are not built yet");
}

}  // namespace cambio::app
