#pragma once

#include <string>

namespace cambio::sim {

/// A headless OpenGL context for MuJoCo's renderer: EGL on the surfaceless Mesa platform (no
/// display, no window, no pbuffer), desktop OpenGL compatibility profile (mjr_* uses the fixed
/// pipeline). On a machine without a GPU, Mesa's llvmpipe renders on the CPU.
/// Construction throws std::runtime_error saying which EGL step failed and what to install.
class EglContext {
 public:
  EglContext();
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  /// Makes the context current on the calling thread if it is not already. A context is
  /// current on one thread at a time: callers serialise (Renderer::Lease).
  void make_current();
  /// Unbinds the context from the calling thread (if bound there), so another thread can take
  /// it.
  void release();
  /// GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  std::string renderer_name();

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
};

}  // namespace cambio::sim
