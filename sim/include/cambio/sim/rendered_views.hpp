#pragma once

#include <optional>
#include <string_view>

#include "cambio/hal/image.hpp"
#include "cambio/sim/egl_context.hpp"

namespace cambio::sim {

/// What a backend that renders its cameras offers the run's report and `--out`
/// (hal::BackendOffers): what renders, and each camera's view whole for images meant for people.
/// Evaluation only: never on a loop.
class RenderedViews {
 public:
  virtual ~RenderedViews() = default;

  /// What the renderer renders with, if one was made (asking never makes one).
  virtual std::optional<RendererDescription> renderer() const = 0;

  /// Renders the newest state of camera `camera_name` whole, at its intrinsics, into `rgb`, when
  /// its frames are not whole (a foveated eye); false, leaving `rgb` alone, when its frames
  /// already are, or the camera is not this backend's.
  virtual bool render_whole_frame(std::string_view camera_name, hal::Image& rgb) = 0;
};

}  // namespace cambio::sim
