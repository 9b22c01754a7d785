#include "renderer_report.hpp"

namespace cambio::app {

namespace {

Json text_or_null(const std::string& text) {
  return text.empty() ? Json(nullptr) : Json(text);
}

}  // namespace

void add_renderer_fields(Json& json, const sim::RendererDescription& description) {
  json["egl_platform"] = description.egl_platform;
  json["gl_renderer"] = description.gl_renderer;
  json["gl_vendor"] = description.gl_vendor;
  json["egl_fallback_reason"] = text_or_null(description.fallback_reason);
}

Json egl_devices_json(const std::vector<sim::EglDevice>& devices) {
  Json list = Json::array();
  for (const auto& device : devices) {
    list.push_back({{"index", device.index},
                    {"software", device.software},
                    {"drm_device_file", text_or_null(device.drm_device_file)},
                    {"drm_render_node", text_or_null(device.drm_render_node)}});
  }
  return list;
}

}  // namespace cambio::app
