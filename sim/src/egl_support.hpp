#pragma once

// Small readings of EGL's C API shared by the device enumeration and the context (internal to
// sim).

#include <string>
#include <string_view>

#include <EGL/egl.h>

namespace cambio::sim {

/// The name of the error eglGetError() returns now ("EGL_BAD_MATCH"); clears it.
std::string egl_error_name();

/// Whether the space-separated extension list `extensions` (may be null) names `extension`
/// exactly (EGL_EXT_device_drm is not EGL_EXT_device_drm_render_node).
bool has_egl_extension(const char* extensions, std::string_view extension);

}  // namespace cambio::sim
