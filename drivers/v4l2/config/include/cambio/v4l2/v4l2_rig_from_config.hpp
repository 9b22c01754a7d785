#pragma once

#include "cambio/config/rig_config.hpp"
#include "cambio/v4l2/v4l2_camera_settings.hpp"

namespace cambio::v4l2 {

/// Every camera entry's device settings, whichever backend the camera names (the backend's
/// check refuses settings on a camera that is not its own).
V4l2RigInfo v4l2_rig_from_config(const config::RigConfig& rig);

}  // namespace cambio::v4l2
