#pragma once

#include <string>
#include <vector>

#include "cambio/config/rig_config.hpp"
#include "cambio/perception/perception_config.hpp"

namespace cambio::app {

/// What a foveated sim eye (config::SimFoveationConfig) withholds from the SSM: each retina level
/// whose blocks are finer than the periphery's pixels but reaches, with its apron, beyond the
/// full-resolution fovea, as one warning naming the camera, the level and the fovea it needs.
/// Such a level reads the upsampled periphery there: a choice (speed over the finest detail), so
/// a warning rather than an error. Empty when every such level fits. Allocates (setup time).
std::vector<std::string> foveation_warnings(const config::CameraConfig& camera,
                                            const perception::SsmConfig& ssm);

}  // namespace cambio::app
