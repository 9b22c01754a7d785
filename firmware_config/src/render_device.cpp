#include "cambio/config/render_device.hpp"

#include <charconv>
#include <cstdlib>

#include "format.hpp"

namespace cambio::config {

std::optional<RenderDevice> parse_render_device(std::string_view text) {
  if (text == "auto") return RenderDevice{RenderDevice::Kind::kAuto, 0};
  if (text == "surfaceless") return RenderDevice{RenderDevice::Kind::kSurfaceless, 0};
  // from_chars takes a leading '-'; an index is digits only.
  if (text.empty() || text.front() < '0' || text.front() > '9') return std::nullopt;
  int index = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), index);
  if (error != std::errc{} || end != text.data() + text.size()) return std::nullopt;
  return RenderDevice{RenderDevice::Kind::kIndex, index};
}

std::string to_string(const RenderDevice& device) {
  switch (device.kind) {
    case RenderDevice::Kind::kAuto:
      return "auto";
    case RenderDevice::Kind::kSurfaceless:
      return "surfaceless";
    case RenderDevice::Kind::kIndex:
      break;
  }
  return std::to_string(device.index);
}

std::string render_device_mismatch(std::string_view found) {
  return "expected " + std::string(kRenderDeviceValues) + ", found " + in_quotes(found);
}

RenderDeviceChoice choose_render_device(const RenderDevice& rig_device,
                                        const std::string& rig_file) {
  const char* variable = std::getenv(kRenderDeviceVariable);
  if (variable == nullptr || *variable == '\0') {
    return {rig_device, rig_file, "sim.render_device"};
  }
  RenderDeviceChoice choice{{}, "environment", kRenderDeviceVariable};
  const auto device = parse_render_device(variable);
  if (!device) throw ConfigError({choice.issue(render_device_mismatch(variable))});
  choice.device = *device;
  return choice;
}

}  // namespace cambio::config
