#pragma once

#include <string>

#include "cambio/config/render_device.hpp"

namespace cambio::sim {

/// What a context renders on, for reports.
struct RendererDescription {
  std::string egl_platform;     ///< "device 1 (/dev/dri/renderD128)" or "Mesa surfaceless".
  std::string gl_renderer;      ///< GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  std::string gl_vendor;        ///< GL_VENDOR, e.g. "Mesa".
  std::string fallback_reason;  ///< Why `auto` rendered on Mesa surfaceless; "" if it did not.

  /// "llvmpipe (LLVM 15.0.6, 256 bits), Mesa, on Mesa surfaceless (auto fell back: ...)".
  std::string summary() const;
};

/// A headless OpenGL context for MuJoCo's renderer: desktop OpenGL, compatibility profile (mjr_*
/// uses the fixed pipeline), made current with no surface (MuJoCo renders into its own
/// framebuffer object; EGL_KHR_surfaceless_context). Its display is an EGL device's
/// (EGL_PLATFORM_DEVICE_EXT, a GPU where one exists) or Mesa's surfaceless platform (no display,
/// no window; llvmpipe renders on the CPU where there is no GPU Mesa drives).
class EglContext {
 public:
  /// Opens the display `choice` names (config::choose_render_device):
  ///  - surfaceless: Mesa's surfaceless platform;
  ///  - an index: that EGL device (enumerate_egl_devices()). A device that does not exist or
  ///    cannot render throws config::ConfigError at the choice's file and key, listing the
  ///    devices found; it is never replaced by another;
  ///  - auto: the first EGL device that is not a software rasteriser; Mesa surfaceless when
  ///    there is none or it cannot render, with the reason in description().fallback_reason.
  /// Throws std::runtime_error saying which EGL step failed and what to install when Mesa
  /// surfaceless is needed and fails. Leaves the context current on the calling thread.
  explicit EglContext(const config::RenderDeviceChoice& choice);
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  /// Makes the context current on the calling thread if it is not already. A context is
  /// current on one thread at a time: callers serialise (Renderer::Lease).
  void make_current();
  /// Unbinds the context from the calling thread (if bound there), so another thread can take
  /// it.
  void release();
  /// Read once at construction; thread-safe.
  const RendererDescription& description() const { return description_; }

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  RendererDescription description_;
};

}  // namespace cambio::sim
