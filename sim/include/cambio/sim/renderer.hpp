#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "cambio/sim/egl_context.hpp"
#include "cambio/sim/render_stall_watchdog.hpp"
#include "cambio/sim/world.hpp"
#include "cambio/sim/world_snapshot.hpp"

struct mjvScene_;
struct mjvOption_;
struct mjrContext_;

namespace cambio::sim {

/// What a view draws. The eyes' defaults: no shadows, no reflections (MSAA is
/// off in the model), the head that carries them hidden.
struct ViewOptions {
  bool shadows = false;
  bool reflections = false;
  bool show_head = false;  ///< Draw geom group 3 (the camera-carrying head); third-person only.
  /// MuJoCo's skybox instead of the eyes' flat sky planes: prettier, about 10 ms more per
  /// 640x480 frame on llvmpipe. For third-person views.
  bool skybox = false;
  /// Trilinear texture filtering (GL_LINEAR_MIPMAP_LINEAR, MuJoCo's). The eyes sample the nearest
  /// mipmap level bilinearly instead: their retina averages blocks of pixels anyway, and
  /// llvmpipe shades a textured fragment about a fifth faster. For third-person views.
  bool trilinear_textures = false;
};

/// A rectangle of a camera's image, drawn at 1 / downscale of its resolution: the pixels
/// [x0, x0 + width * downscale) x [y0, y0 + height * downscale) of the full image (top-left
/// origin) drawn into width x height pixels. The whole image at full resolution by default.
struct ImageWindow {
  int full_width_px = 0;
  int full_height_px = 0;
  int x0_px = 0;
  int y0_px = 0;
  int width_px = 0;
  int height_px = 0;
  int downscale = 1;

  static ImageWindow whole(int width_px, int height_px, int downscale = 1) {
    return {width_px, height_px, 0, 0, width_px / downscale, height_px / downscale, downscale};
  }
  static ImageWindow centred(int full_width_px, int full_height_px, int size_px) {
    return {full_width_px,
            full_height_px,
            (full_width_px - size_px) / 2,
            (full_height_px - size_px) / 2,
            size_px,
            size_px,
            1};
  }
  bool is_whole() const {
    return x0_px == 0 && y0_px == 0 && downscale == 1 && width_px == full_width_px &&
           height_px == full_height_px;
  }
};

/// MuJoCo's OpenGL renderer on a headless EGL context, with its own copy of the world state
/// (a private mjData filled from WorldSnapshot), so it never reads the physics loop's data.
/// One per world, shared by that world's cameras and ground truth. One GL context serves one
/// thread at a time: hold a Lease around set_state() and render().
class Renderer {
 public:
  /// The calling thread's exclusive use of the renderer, for the lease's lifetime. Not a lock:
  /// kTry gives up at once when another thread holds the renderer (the camera loop, which must
  /// never wait); kWait spins, yielding, until it is free (evaluation code outside the loops).
  class Lease {
   public:
    enum class Mode : std::uint8_t { kTry, kWait };
    Lease(Renderer& renderer, Mode mode) noexcept;
    ~Lease();
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    /// True if this lease holds the renderer.
    explicit operator bool() const noexcept { return held_; }

   private:
    Renderer& renderer_;
    bool held_ = false;
  };

  /// Allocates everything (GL context, framebuffers, textures, scene). The GL context is on the
  /// render device of config::choose_render_device: CAMBIO_EGL_DEVICE, else the rig's
  /// sim.render_device (see EglContext). Throws config::ConfigError for a bad CAMBIO_EGL_DEVICE,
  /// a chosen device that does not exist or cannot render, or the rig's cameras larger than this
  /// GL implementation draws (GL_MAX_RENDERBUFFER_SIZE, GL_MAX_TEXTURE_SIZE,
  /// GL_MAX_VIEWPORT_DIMS); std::runtime_error or MujocoError; OutOfMemory for memory. Under an
  /// address-space limit a RenderStallWatchdog ends the process (exit 1, said as out of memory)
  /// if starting or rendering makes no progress for 15 s: Mesa's way of running out there.
  explicit Renderer(const World& world);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Copies `snapshot` into the render state and runs kinematics. Caller holds a Lease.
  /// Real-time safe.
  void set_state(const WorldSnapshot& snapshot) noexcept;
  /// Step count of the snapshot last set (so a camera can tell whether it must set its own).
  std::uint64_t state_step() const { return state_step_; }
  std::int64_t state_stamp_ns() const { return state_stamp_ns_; }
  /// False until the first set_state() (the renderer then shows the world at construction).
  bool has_state() const { return has_state_; }

  /// Renders MuJoCo camera `camera_id` at width x height into the offscreen buffer and reads
  /// it back: `rgb` (3 bytes per pixel) and/or `depth` (metres along the optical axis), both
  /// bottom row first as OpenGL gives them; either may be null. Caller holds a Lease. Returns
  /// false if MuJoCo reported an error. Real-time safe (no allocation); takes milliseconds.
  bool render(int camera_id, int width_px, int height_px, const ViewOptions& view,
              std::uint8_t* rgb, float* depth) noexcept;
  /// Renders `window` of camera `camera_id`'s image (its frustum narrowed to the window) into
  /// window.width_px x window.height_px pixels of `rgb` and/or `depth`, as render() does.
  bool render(int camera_id, const ImageWindow& window, const ViewOptions& view, std::uint8_t* rgb,
              float* depth) noexcept;

  /// The raw steps MuJoCo takes for one view (scene update, render, read back RGB), with the
  /// eye defaults: the reference `cambio sim-bench` compares the camera pipeline with. Caller
  /// holds a Lease.
  void render_raw_reference(int camera_id, int width_px, int height_px, std::uint8_t* rgb);

  const World& world() const { return world_; }
  /// MuJoCo id of the scene's overview camera (-1 if the model has none).
  int overview_camera_id() const;
  /// The render-side state (after set_state): poses of bodies, cameras (xpos, xmat).
  const mjData_* state() const { return data_; }
  /// The EGL platform and GL implementation it renders with. Thread-safe.
  const RendererDescription& description() const { return egl_.description(); }
  double near_m() const { return near_m_; }
  double far_m() const { return far_m_; }

 private:
  void apply_view(const ViewOptions& view);
  void set_texture_filter(bool trilinear);

  const World& world_;
  /// Under an address-space limit only (else null); declared before egl_ so that it watches the
  /// EGL start as well.
  std::unique_ptr<RenderStallWatchdog> watchdog_;
  EglContext egl_;
  std::atomic_flag busy_;  ///< Set while a Lease holds the renderer.
  mjData_* data_ = nullptr;
  std::unique_ptr<mjvScene_> scene_;
  std::unique_ptr<mjvOption_> option_;
  std::unique_ptr<mjrContext_> context_;
  std::uint64_t state_step_ = 0;
  std::int64_t state_stamp_ns_ = 0;
  bool has_state_ = false;
  bool textures_trilinear_ = true;  ///< What mjr_makeContext set.
  double near_m_ = 0.0;
  double far_m_ = 0.0;
};

}  // namespace cambio::sim
