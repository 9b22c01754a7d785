#pragma once

// How the commands report the sim's renderer: which EGL platform and GL implementation drew the
// cameras, and the EGL devices there were to choose from.

#include <vector>

#include "cambio/sim/egl_context.hpp"
#include "cambio/sim/egl_devices.hpp"
#include "json_output.hpp"

namespace cambio::app {

/// Sets "egl_platform", "gl_renderer", "gl_vendor" and "egl_fallback_reason" (null when auto
/// did not fall back) in `json`: sim-bench's --json at its top level, run's summary.json under
/// "renderer".
void add_renderer_fields(Json& json, const sim::RendererDescription& description);

/// One object per device: "index", "software", "drm_device_file" and "drm_render_node" (null
/// when the device has none).
Json egl_devices_json(const std::vector<sim::EglDevice>& devices);

}  // namespace cambio::app
