#pragma once

#include <cstddef>

#include "cambio/config/experiment_config.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/perception/sensory_servo.hpp"

namespace cambio::app {

/// The SSM's settings for the rig's stereo pair (cameras `left` and `right`, rig order): the
/// experiment's perception file (or the shipped default), a disparity scan range from the pair's
/// geometry when the file gives none, and a warning on stderr for each eye whose foveation does
/// not suit them. The same on the robot and on a perception host given the same experiment.
/// Throws config::ConfigError for a bad perception file.
perception::SsmConfig stereo_ssm_config(const config::ExperimentConfig& experiment,
                                        const hal::HardwareInfo& hardware, std::size_t left,
                                        std::size_t right);

}  // namespace cambio::app
