#pragma once

#include <string>
#include <vector>

namespace cambio::sim {

/// One EGL device as eglQueryDevicesEXT lists it (EGL_EXT_device_enumeration): a GPU, or Mesa's
/// software rasteriser (llvmpipe), which Mesa lists as a device too.
struct EglDevice {
  int index = 0;                ///< Position in eglQueryDevicesEXT's list.
  std::string drm_device_file;  ///< EGL_DRM_DEVICE_FILE_EXT ("/dev/dri/card0"); empty if none.
  std::string drm_render_node;  ///< EGL_DRM_RENDER_NODE_FILE_EXT ("/dev/dri/renderD128").
  bool software = false;        ///< Its extensions name EGL_MESA_device_software.
  void* handle = nullptr;       ///< The EGLDeviceEXT; valid for the process's lifetime.

  /// The node a person recognises it by: the render node, else the DRM device file, else "".
  const std::string& node() const {
    return drm_render_node.empty() ? drm_device_file : drm_render_node;
  }
  /// "device 1 (/dev/dri/renderD128)", "device 0 (software rasteriser)": how a renderer's
  /// platform is reported.
  std::string name() const;
  /// "device 1: hardware, /dev/dri/card1, render node /dev/dri/renderD128",
  /// "device 0: software rasteriser, no DRM device file": how a list of devices shows it.
  std::string describe() const;
};

/// Every EGL device, in EGL's order. Throws std::runtime_error naming the missing piece when the
/// EGL library cannot enumerate devices (no EGL_EXT_device_enumeration / EGL_EXT_device_query,
/// or eglQueryDevicesEXT fails). Not real-time safe (allocates, may load EGL vendor libraries).
std::vector<EglDevice> enumerate_egl_devices();

/// Each device's describe(), joined by "; ", or "none": the devices a message lists.
std::string describe_egl_devices(const std::vector<EglDevice>& devices);

}  // namespace cambio::sim
