#include "sim_camera.hpp"

#include <cstring>
#include <stdexcept>
#include <string>

#include "cambio/hal/luma.hpp"
#include "foveated_frame.hpp"

namespace cambio::sim {

namespace {

// The rig loader refuses a foveation that does not tile the image; a config built in code must
// not slip past (a fovea outside the frame would be written out of bounds).
config::SimFoveationConfig checked(const config::SimFoveationConfig& foveation,
                                   const hal::CameraInfo& info) {
  const int w = info.intrinsics.width_px;
  const int h = info.intrinsics.height_px;
  if (!foveation.fits(w, h)) {
    throw std::invalid_argument("sim camera '" + info.name + "': foveation (periphery 1/" +
                                std::to_string(foveation.periphery_downscale) + ", fovea " +
                                std::to_string(foveation.fovea_px) + " px) does not tile its " +
                                std::to_string(w) + "x" + std::to_string(h) + " image");
  }
  return foveation;
}

}  // namespace

SimCamera::SimCamera(hal::CameraInfo info, int camera_id, Renderer& renderer, CameraFrames& frames,
                     double noise_std, std::uint64_t seed, config::SimFoveationConfig foveation)
    : info_(std::move(info)),
      camera_id_(camera_id),
      renderer_(renderer),
      frames_(frames),
      noise_(noise_std, seed),
      lens_(info_.distortion.is_zero() ? std::nullopt : std::make_optional<SimLens>(info_)),
      // Through a lens every distorted pixel may read anywhere in the ideal window: whole frames.
      foveation_(lens_ ? config::SimFoveationConfig{} : checked(foveation, info_)),
      rgb_(lens_ ? lens_->ideal_bytes()
                 : static_cast<std::size_t>(info_.intrinsics.width_px /
                                            foveation_.periphery_downscale) *
                       static_cast<std::size_t>(info_.intrinsics.height_px /
                                                foveation_.periphery_downscale) *
                       3),
      fovea_(foveation_.enabled() ? static_cast<std::size_t>(foveation_.fovea_px) *
                                        static_cast<std::size_t>(foveation_.fovea_px) * 3
                                  : 0) {
  // Mesa's llvmpipe compiles shader variants with LLVM on first use, which allocates through
  // operator new. Render once here, through this eye and through the overview (which sees every
  // material of the scene), so grab() never triggers a compile.
  const Renderer::Lease lease(renderer_, Renderer::Lease::Mode::kWait);
  const int width = info_.intrinsics.width_px;
  const int height = info_.intrinsics.height_px;
  (void)render_views();
  const int overview = renderer_.overview_camera_id();
  if (overview >= 0) {
    const int downscale = foveation_.periphery_downscale;
    (void)renderer_.render(overview, width / downscale, height / downscale, ViewOptions{},
                           rgb_.data(), nullptr);
  }
}

bool SimCamera::render_views() noexcept {
  const int width = info_.intrinsics.width_px;
  const int height = info_.intrinsics.height_px;
  if (lens_)
    return renderer_.render(camera_id_, lens_->window(), ViewOptions{}, rgb_.data(), nullptr);
  if (!foveation_.enabled()) {
    return renderer_.render(camera_id_, width, height, ViewOptions{}, rgb_.data(), nullptr);
  }
  return renderer_.render(camera_id_,
                          ImageWindow::whole(width, height, foveation_.periphery_downscale),
                          ViewOptions{}, rgb_.data(), nullptr) &&
         renderer_.render(camera_id_, ImageWindow::centred(width, height, foveation_.fovea_px),
                          ViewOptions{}, fovea_.data(), nullptr);
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
      out.pixels.size() != static_cast<std::size_t>(intrinsics.width_px) *
                               static_cast<std::size_t>(intrinsics.height_px) *
                               static_cast<std::size_t>(out.channels())) {
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
    if (!render_views()) return hal::Status::kFault;
    rendered_step_ = frame->step;
    stamp_ns = frame->stamp_ns;
  }
  if (lens_) {
    lens_->apply(rgb_.data(), out);
  } else if (foveation_.enabled()) {
    compose_foveated(rgb_.data(), foveation_.periphery_downscale, fovea_.data(),
                     foveation_.fovea_px, out);
  } else {
    convert_rows(rgb_.data(), intrinsics.width_px, intrinsics.height_px, info_.format, out);
  }
  noise_.apply(out.pixels);
  out.stamp_ns = stamp_ns;
  out.sequence = ++sequence_;
  return hal::Status::kOk;
}

}  // namespace cambio::sim
