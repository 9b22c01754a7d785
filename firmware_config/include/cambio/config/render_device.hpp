#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "cambio/config/config_error.hpp"

namespace cambio::config {

/// Which EGL display the sim renders its cameras on: the rig's `sim.render_device`, which the
/// environment variable CAMBIO_EGL_DEVICE overrides (sim::choose_render_device). Both take the
/// same text: "auto", "surfaceless" or a device index "0", "1", ...
struct RenderDevice {
  enum class Kind : std::uint8_t {
    kAuto,         ///< The first EGL device that is not a software rasteriser, else kSurfaceless.
    kSurfaceless,  ///< Mesa's surfaceless platform (llvmpipe on a machine without a GPU).
    kIndex,        ///< Device `index` of eglQueryDevicesEXT's list; never replaced by another.
  };
  Kind kind = Kind::kAuto;
  int index = 0;  ///< For kIndex: 0-based, as eglQueryDevicesEXT lists the devices.

  bool operator==(const RenderDevice&) const = default;
};

/// The values a render device accepts, as messages list them.
inline constexpr std::string_view kRenderDeviceValues =
    "auto, surfaceless or an EGL device index (0, 1, ...)";

/// Parses "auto", "surfaceless" or a decimal index (digits only, no sign); nullopt otherwise.
std::optional<RenderDevice> parse_render_device(std::string_view text);

/// "auto", "surfaceless" or the index: what parse_render_device reads back.
std::string to_string(const RenderDevice& device);

/// The environment variable that overrides every rig's `sim.render_device`.
inline constexpr const char* kRenderDeviceVariable = "CAMBIO_EGL_DEVICE";

/// A render device and where it was chosen, so a message about it names the place to fix.
struct RenderDeviceChoice {
  RenderDevice device;
  std::string file;  ///< The rig file, or "environment" for CAMBIO_EGL_DEVICE.
  std::string key;   ///< "sim.render_device", or "CAMBIO_EGL_DEVICE".

  bool from_environment() const { return key == kRenderDeviceVariable; }
  /// An issue about this choice (no line: the sim finds it out after loading).
  ConfigIssue issue(std::string message) const { return {file, 0, 0, key, std::move(message)}; }
};

/// CAMBIO_EGL_DEVICE when it is set and not empty (it overrides the rig: one machine's GPU is a
/// property of the machine, not of the robot), else `rig_device` as read from `rig_file`.
/// Throws ConfigError (file "environment", key CAMBIO_EGL_DEVICE) when the variable holds a value
/// parse_render_device refuses. Reads the environment: not thread-safe against setenv().
RenderDeviceChoice choose_render_device(const RenderDevice& rig_device,
                                        const std::string& rig_file);

/// `expected auto, surfaceless or an EGL device index (0, 1, ...), found "gpu"`: the message
/// for a value parse_render_device refuses (the value echoed, cut if long).
std::string render_device_mismatch(std::string_view found);

}  // namespace cambio::config
