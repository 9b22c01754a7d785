#include "sim_camera.hpp"

#include <cstring>

#include "cambio/hal/luma.hpp"

namespace cambio::sim {

SimCamera::SimCamera(hal::CameraInfo info, int camera_id, Renderer& renderer, CameraFrames& frames,
                     double noise_std, std::uint64_t seed)
    : info_(std::move(info)),
      camera_id_(camera_id),
      renderer_(renderer),
      frames_(frames),
      noise_(noise_std, seed),
      rgb_(static_cast<std::size_t>(info_.intrinsics.width_px) *
           static_cast<std::size_t>(info_.intrinsics.height_px) * 3) {
  // Mesa's llvmpipe compiles shader variants with LLVM on first use, which allocates through
  // operator new. Render once here, through this eye and through the overview (which sees every
  // material of the scene), so grab() never triggers a compile.
  const Renderer::Lease lease(renderer_, Renderer::Lease::Mode::kWait);
  const int width = info_.intrinsics.width_px;
  const int height = info_.intrinsics.height_px;
  (void)renderer_.render(camera_id_, width, height, ViewOptions{}, rgb_.data(), nullptr);
  const int overview = renderer_.overview_camera_id();
  if (overview >= 0) {
    (void)renderer_.render(overview, width, height, ViewOptions{}, rgb_.data(), nullptr);
  }
}

void SimCamera::convert_rows(const std::uint8_t* rgb_bottom_up, int width, int height,
                             hal::PixelFormat format, hal::Image& out) noexcept {
  const std::size_t row_bytes = static_cast<std::size_t>(width) * 3;
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* source =
        rgb_bottom_up + static_cast<std::size_t>(height - 1 - y) * row_bytes;
    std::uint8_t* target = out.row(y);
    if (format == hal::PixelFormat::kRgb8) {
      std::memcpy(target, source, row_bytes);
    } else {
      for (int x = 0; x < width; ++x) {
        target[x] = hal::luma_bt601(source[3 * x], source[3 * x + 1], source[3 * x + 2]);
      }
    }
  }
}

hal::Status SimCamera::grab(hal::Image& out) {
  const auto& intrinsics = info_.intrinsics;
  if (out.width_px != intrinsics.width_px || out.height_px != intrinsics.height_px ||
      out.format != info_.format ||
      out.pixels.size() != rgb_.size() / 3 * static_cast<std::size_t>(out.channels())) {
    return hal::Status::kRejected;
  }
  std::int64_t stamp_ns = 0;
  {
    // Never wait for the renderer: a camera loop that finds it taken (ground truth rendering on
    // another thread) skips this cycle's image.
    const Renderer::Lease lease(renderer_, Renderer::Lease::Mode::kTry);
    if (!lease) return hal::Status::kNoNewData;
    const WorldSnapshot* frame = frames_.frame_for(rendered_step_);
    if (frame == nullptr || rendered_step_ == frame->step) return hal::Status::kNoNewData;
    // Ground truth may have left the renderer at another instant.
    if (!renderer_.has_state() || renderer_.state_step() != frame->step) {
      renderer_.set_state(*frame);
    }
    if (!renderer_.render(camera_id_, intrinsics.width_px, intrinsics.height_px, ViewOptions{},
                          rgb_.data(), nullptr)) {
      return hal::Status::kFault;
    }
    rendered_step_ = frame->step;
    stamp_ns = frame->stamp_ns;
  }
  convert_rows(rgb_.data(), intrinsics.width_px, intrinsics.height_px, info_.format, out);
  noise_.apply(out.pixels);
  out.stamp_ns = stamp_ns;
  out.sequence = ++sequence_;
  return hal::Status::kOk;
}

}  // namespace cambio::sim
