#include "cambio/sim/egl_context.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <vector>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>

#include "cambio/sim/address_space_limit.hpp"
#include "cambio/sim/egl_devices.hpp"
#include "egl_support.hpp"

namespace cambio::sim {

namespace {

constexpr const char* kSurfacelessPlatform = "Mesa surfaceless";
constexpr const char* kMesaPackages = "Debian: libegl-mesa0 libgl1-mesa-dri";

/// One step of opening a display or a context failed: which, and EGL's error.
class EglStepFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[noreturn]] void step_failed(const std::string& step) {
  throw EglStepFailed(step + " failed (" + egl_error_name() + ")");
}

struct OpenContext {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
};

EGLDisplay platform_display(EGLenum platform, void* native_display, const char* step) {
  auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display == nullptr) step_failed("eglGetProcAddress(eglGetPlatformDisplayEXT)");
  EGLDisplay display = get_platform_display(platform, native_display, nullptr);
  if (display == EGL_NO_DISPLAY) step_failed(step);
  return display;
}

/// Initialises `display` and creates the desktop OpenGL compatibility context on it, current on
/// this thread with no surface. A display is never terminated here, even when a later step fails
/// (see ~EglContext).
OpenContext open_context(EGLDisplay display) {
  EGLint major = 0, minor = 0;
  if (eglInitialize(display, &major, &minor) != EGL_TRUE) step_failed("eglInitialize");
  if (!has_egl_extension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context")) {
    throw EglStepFailed(
        "the display lacks EGL_KHR_surfaceless_context (the context is made current with no "
        "surface: MuJoCo renders into its own framebuffer)");
  }
  const EGLint config_attributes[] = {EGL_SURFACE_TYPE,
                                      EGL_PBUFFER_BIT,
                                      EGL_RED_SIZE,
                                      8,
                                      EGL_GREEN_SIZE,
                                      8,
                                      EGL_BLUE_SIZE,
                                      8,
                                      EGL_DEPTH_SIZE,
                                      24,
                                      EGL_RENDERABLE_TYPE,
                                      EGL_OPENGL_BIT,
                                      EGL_NONE};
  EGLConfig config = nullptr;
  EGLint config_count = 0;
  if (eglChooseConfig(display, config_attributes, &config, 1, &config_count) != EGL_TRUE ||
      config_count < 1) {
    // Surfaceless configs may not advertise pbuffer support; MuJoCo renders into its own
    // framebuffer object, so any OpenGL-capable config will do.
    const EGLint fallback[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    if (eglChooseConfig(display, fallback, &config, 1, &config_count) != EGL_TRUE ||
        config_count < 1) {
      step_failed("eglChooseConfig (desktop OpenGL)");
    }
  }
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) step_failed("eglBindAPI(EGL_OPENGL_API)");
  const EGLint context_attributes[] = {EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                       EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
  if (context == EGL_NO_CONTEXT) step_failed("eglCreateContext (OpenGL compatibility profile)");
  if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context) != EGL_TRUE) {
    const std::string failed = "eglMakeCurrent (no surface) failed (" + egl_error_name() + ")";
    eglDestroyContext(display, context);
    throw EglStepFailed(failed);
  }
  return {display, context};
}

OpenContext open_device(const EglDevice& device) {
  if (!has_egl_extension(eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS),
                         "EGL_EXT_platform_device")) {
    throw EglStepFailed("the EGL library lacks EGL_EXT_platform_device");
  }
  return open_context(platform_display(EGL_PLATFORM_DEVICE_EXT, device.handle,
                                       "eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT)"));
}

/// Mesa's surfaceless platform; `why` (may be empty) says why it is used when it fails.
OpenContext open_surfaceless(const std::string& why) {
  try {
    if (!has_egl_extension(eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS),
                           "EGL_MESA_platform_surfaceless")) {
      throw EglStepFailed("EGL_MESA_platform_surfaceless is not available");
    }
    return open_context(
        platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY,
                         "eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)"));
  } catch (const EglStepFailed& failed) {
    std::string message = "offscreen rendering on Mesa surfaceless: ";
    message += failed.what();
    // Under an address-space limit the packages are there and memory is what is missing.
    const std::string limit_note = address_space_limit_note();
    if (!limit_note.empty()) throw OutOfMemory(message + limit_note);
    message += "; the sim needs EGL with Mesa's surfaceless platform (";
    message += kMesaPackages;
    message += ")";
    if (!why.empty()) message += " (auto fell back to it: " + why + ")";
    throw std::runtime_error(message);
  }
}

/// The device `choice` names, or a config::ConfigError at its key that lists the devices; sets
/// `platform` to the device's name.
OpenContext open_chosen_device(const config::RenderDeviceChoice& choice, std::string& platform) {
  const std::string instead = "; or set " + choice.key + " to auto or surfaceless";
  std::vector<EglDevice> devices;
  try {
    devices = enumerate_egl_devices();
  } catch (const std::runtime_error& error) {
    throw config::ConfigError(
        {choice.issue("expected an EGL device index, found " + config::to_string(choice.device) +
                      ", but no EGL device can be listed: " + error.what() + instead)});
  }
  const auto index = static_cast<std::size_t>(choice.device.index);
  if (index >= devices.size()) {
    const std::string accepted =
        devices.empty() ? "an EGL device index, but EGL lists no device"
                        : "an EGL device index in [0, " + std::to_string(devices.size() - 1) + "]";
    throw config::ConfigError(
        {choice.issue("expected " + accepted + ", found " + config::to_string(choice.device) +
                      " (devices: " + describe_egl_devices(devices) + ")" + instead)});
  }
  const EglDevice& device = devices[index];
  try {
    OpenContext context = open_device(device);
    platform = device.name();
    return context;
  } catch (const EglStepFailed& failed) {
    throw config::ConfigError({choice.issue(
        device.name() + " cannot render: " + failed.what() +
        " (devices: " + describe_egl_devices(devices) + "); check its EGL driver" +
        (device.node().empty() ? "" : " and that this user may open " + device.node()) + instead)});
  }
}

/// `auto`'s choice: the first device that is not a software rasteriser, setting `platform` to its
/// name; nullopt with `reason` set when there is none, it cannot render, or the devices cannot be
/// listed.
std::optional<OpenContext> open_first_hardware_device(std::string& platform, std::string& reason) {
  std::vector<EglDevice> devices;
  try {
    devices = enumerate_egl_devices();
  } catch (const std::runtime_error& error) {
    reason = error.what();
    return std::nullopt;
  }
  const auto hardware = std::find_if(devices.begin(), devices.end(),
                                     [](const EglDevice& device) { return !device.software; });
  if (hardware == devices.end()) {
    reason = "no hardware EGL device (devices: " + describe_egl_devices(devices) + ")";
    return std::nullopt;
  }
  try {
    OpenContext context = open_device(*hardware);
    platform = hardware->name();
    return context;
  } catch (const EglStepFailed& failed) {
    reason = hardware->name() + " cannot render: " + failed.what();
    return std::nullopt;
  }
}

std::string gl_string(GLenum name) {
  const auto* text = glGetString(name);
  return text != nullptr ? reinterpret_cast<const char*>(text) : "unknown";
}

}  // namespace

std::string RendererDescription::summary() const {
  std::string text = gl_renderer + ", " + gl_vendor + ", on " + egl_platform;
  if (!fallback_reason.empty()) text += " (auto fell back: " + fallback_reason + ")";
  return text;
}

EglContext::EglContext(const config::RenderDeviceChoice& choice) {
  OpenContext context;
  switch (choice.device.kind) {
    case config::RenderDevice::Kind::kSurfaceless:
      context = open_surfaceless("");
      description_.egl_platform = kSurfacelessPlatform;
      break;
    case config::RenderDevice::Kind::kIndex:
      context = open_chosen_device(choice, description_.egl_platform);
      break;
    case config::RenderDevice::Kind::kAuto: {
      std::string reason;
      if (auto hardware = open_first_hardware_device(description_.egl_platform, reason)) {
        context = *hardware;
      } else {
        context = open_surfaceless(reason);
        description_.egl_platform = kSurfacelessPlatform;
        description_.fallback_reason = reason;
      }
      break;
    }
  }
  display_ = context.display;
  context_ = context.context;
  description_.gl_renderer = gl_string(GL_RENDERER);
  description_.gl_vendor = gl_string(GL_VENDOR);
}

EglContext::~EglContext() {
  if (display_ != nullptr) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != nullptr) eglDestroyContext(display_, context_);
    // A display is shared by every context of the process on it: eglGetPlatformDisplayEXT
    // returns the same EGLDisplay for Mesa's surfaceless platform and for the same EGL device,
    // and eglInitialize counts no references. Terminating it would pull it from under another
    // EglContext, so displays are left to process exit.
  }
}

void EglContext::make_current() {
  if (eglGetCurrentContext() == context_) return;
  if (eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) != EGL_TRUE) {
    throw std::runtime_error("offscreen rendering on " + description_.egl_platform +
                             ": eglMakeCurrent (no surface) failed (" + egl_error_name() + ")");
  }
}

void EglContext::release() {
  if (eglGetCurrentContext() == context_) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
}

}  // namespace cambio::sim
