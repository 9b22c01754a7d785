#pragma once

#include <vector>

#include "cambio/hal/backend_factory.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/v4l2/v4l2_camera_settings.hpp"

namespace cambio::v4l2 {

/// The v4l2 backend's check of a rig, before any device is opened: every v4l2 camera names a
/// device node under /dev/ (one camera per node), a pixel format this backend converts (GREY,
/// YUYV; YUYV at an even width) and a frame rate; a camera of another backend gives none of
/// these; a stereo pair of two v4l2 cameras runs them at one rate (they pair by timestamp).
/// Each problem is keyed by its rig path (cameras.<name>.<key>).
std::vector<hal::SettingProblem> check_v4l2_rig(const hal::HardwareInfo& hardware,
                                                const V4l2RigInfo& rig);

}  // namespace cambio::v4l2
