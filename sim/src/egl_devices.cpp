#include "cambio/sim/egl_devices.hpp"

#include <stdexcept>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "egl_support.hpp"

namespace cambio::sim {

namespace {

/// A device string, or "" when the device does not have it (the query's error is cleared).
std::string device_string(PFNEGLQUERYDEVICESTRINGEXTPROC query, EGLDeviceEXT device, EGLint name) {
  const char* text = query(device, name);
  if (text == nullptr) {
    (void)egl_error_name();
    return {};
  }
  return text;
}

}  // namespace

std::string EglDevice::name() const {
  const std::string& file = node();
  if (!file.empty()) return "device " + std::to_string(index) + " (" + file + ")";
  return "device " + std::to_string(index) + (software ? " (software rasteriser)" : "");
}

std::string EglDevice::describe() const {
  std::string text = "device " + std::to_string(index) + ": ";
  text += software ? "software rasteriser" : "hardware";
  text += drm_device_file.empty() ? ", no DRM device file" : ", " + drm_device_file;
  if (!drm_render_node.empty()) text += ", render node " + drm_render_node;
  return text;
}

std::vector<EglDevice> enumerate_egl_devices() {
  // As MuJoCo's EGL backend does: the device functions are extensions, reached through
  // eglGetProcAddress (a libEGL that lacks them returns null).
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  const bool can_enumerate = has_egl_extension(client, "EGL_EXT_device_base") ||
                             (has_egl_extension(client, "EGL_EXT_device_enumeration") &&
                              has_egl_extension(client, "EGL_EXT_device_query"));
  if (!can_enumerate) {
    throw std::runtime_error(
        "EGL device enumeration: the EGL library lacks EGL_EXT_device_enumeration and "
        "EGL_EXT_device_query (Debian: libegl1, libglvnd's dispatcher, with libegl-mesa0)");
  }
  auto query_devices =
      reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto query_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
      eglGetProcAddress("eglQueryDeviceStringEXT"));
  if (query_devices == nullptr || query_string == nullptr) {
    throw std::runtime_error(
        "EGL device enumeration: eglGetProcAddress found no eglQueryDevicesEXT or "
        "eglQueryDeviceStringEXT (Debian: libegl1, libglvnd's dispatcher, with libegl-mesa0)");
  }
  EGLint count = 0;
  if (query_devices(0, nullptr, &count) != EGL_TRUE || count < 0) {
    throw std::runtime_error("EGL device enumeration: eglQueryDevicesEXT failed (" +
                             egl_error_name() + ")");
  }
  std::vector<EGLDeviceEXT> handles(static_cast<std::size_t>(count));
  if (count > 0 && query_devices(count, handles.data(), &count) != EGL_TRUE) {
    throw std::runtime_error("EGL device enumeration: eglQueryDevicesEXT failed (" +
                             egl_error_name() + ")");
  }
  std::vector<EglDevice> devices;
  for (EGLint i = 0; i < count; ++i) {
    EglDevice device;
    device.index = static_cast<int>(i);
    device.handle = handles[static_cast<std::size_t>(i)];
    const std::string extensions = device_string(query_string, device.handle, EGL_EXTENSIONS);
    device.software = has_egl_extension(extensions.c_str(), "EGL_MESA_device_software");
    // Asking a device for a string its extensions do not promise is an EGL_BAD_PARAMETER.
    if (has_egl_extension(extensions.c_str(), "EGL_EXT_device_drm")) {
      device.drm_device_file = device_string(query_string, device.handle, EGL_DRM_DEVICE_FILE_EXT);
    }
    if (has_egl_extension(extensions.c_str(), "EGL_EXT_device_drm_render_node")) {
      device.drm_render_node =
          device_string(query_string, device.handle, EGL_DRM_RENDER_NODE_FILE_EXT);
    }
    devices.push_back(std::move(device));
  }
  return devices;
}

std::string describe_egl_devices(const std::vector<EglDevice>& devices) {
  if (devices.empty()) return "none";
  std::string text;
  for (const auto& device : devices) text += (text.empty() ? "" : "; ") + device.describe();
  return text;
}

}  // namespace cambio::sim
