#include "cambio/sim/renderer.hpp"

#include <algorithm>
#include <thread>
#include <vector>

#include <GL/gl.h>
#include <mujoco/mujoco.h>

#include "cambio/config/config_error.hpp"
#include "cambio/sim/address_space_limit.hpp"
#include "cambio/sim/mujoco_error.hpp"
#include "view_culling.hpp"

namespace cambio::sim {

namespace {

// The offscreen framebuffer holds the largest camera (MjcfOptions); a GL implementation that
// cannot allocate it reports an incomplete framebuffer, which MuJoCo turns into an error that
// names neither the camera nor the limit. Checked first: each camera larger than the limit is
// named. Requires a current context.
void check_framebuffer_limits(const World& world, int offscreen_width_px, int offscreen_height_px) {
  GLint renderbuffer = 0;
  GLint texture = 0;
  GLint viewport[2] = {0, 0};
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbuffer);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &texture);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport);
  const int limit = std::min({renderbuffer, texture, viewport[0], viewport[1]});
  if (limit <= 0 || (offscreen_width_px <= limit && offscreen_height_px <= limit)) return;
  std::vector<config::ConfigIssue> issues;
  const config::RigConfig& rig = world.rig();
  for (const auto& camera : rig.cameras) {
    if (camera.width_px > limit || camera.height_px > limit) {
      issues.push_back({rig.source_file, 0, 0, "cameras." + camera.name,
                        "this renderer draws at most " + std::to_string(limit) +
                            " px a side, found " + std::to_string(camera.width_px) + "x" +
                            std::to_string(camera.height_px)});
    }
  }
  if (issues.empty()) {
    throw MujocoError("offscreen rendering: a " + std::to_string(offscreen_width_px) + "x" +
                      std::to_string(offscreen_height_px) +
                      " px view is larger than this renderer's " + std::to_string(limit) +
                      " px a side");
  }
  throw config::ConfigError(std::move(issues));
}

// The projection of `window` of the camera's image: MuJoCo's frustum for the whole image (its
// near-plane extents from fovy, centred) cut down to the window's pixels. mjr_render sets the
// horizontal extent from the viewport's aspect, which is the window's own.
void narrow_frustum(mjvGLCamera& camera, const ImageWindow& window) {
  const float pixel =
      (camera.frustum_top - camera.frustum_bottom) / static_cast<float>(window.full_height_px);
  const float full_left = camera.frustum_center - 0.5F * pixel * window.full_width_px;
  const float full_top = camera.frustum_top;
  const float span_x = static_cast<float>(window.width_px * window.downscale);
  const float span_y = static_cast<float>(window.height_px * window.downscale);
  camera.frustum_top = full_top - pixel * static_cast<float>(window.y0_px);
  camera.frustum_bottom = full_top - pixel * (static_cast<float>(window.y0_px) + span_y);
  camera.frustum_center = full_left + pixel * (static_cast<float>(window.x0_px) + 0.5F * span_x);
}

std::unique_ptr<RenderStallWatchdog> armed_watchdog(const char* step) {
  std::unique_ptr<RenderStallWatchdog> watchdog = RenderStallWatchdog::under_address_space_limit();
  if (watchdog) watchdog->arm(step);
  return watchdog;
}

}  // namespace

Renderer::Lease::Lease(Renderer& renderer, Mode mode) noexcept : renderer_(renderer) {
  held_ = !renderer_.busy_.test_and_set(std::memory_order_acquire);
  while (!held_ && mode == Mode::kWait) {
    std::this_thread::yield();
    held_ = !renderer_.busy_.test_and_set(std::memory_order_acquire);
  }
}

Renderer::Lease::~Lease() {
  if (held_) renderer_.busy_.clear(std::memory_order_release);
}

Renderer::Renderer(const World& world)
    : world_(world),
      watchdog_(armed_watchdog("starting the renderer")),
      egl_(config::choose_render_device(world.rig().sim.render_device, world.rig().source_file)),
      scene_(std::make_unique<mjvScene>()),
      option_(std::make_unique<mjvOption>()),
      context_(std::make_unique<mjrContext>()) {
  install_mujoco_handlers();
  const mjModel* model = world_.model();
  data_ = mj_makeData(model);
  if (data_ == nullptr) throw MujocoError("MuJoCo: could not allocate the renderer's mjData");
  mj_copyData(data_, model, world_.data());
  mj_kinematics(model, data_);
  mj_camlight(model, data_);
  mjv_defaultOption(option_.get());
  mjv_defaultScene(scene_.get());
  mjr_defaultContext(context_.get());
  try {
    egl_.make_current();
    check_framebuffer_limits(world_, model->vis.global.offwidth, model->vis.global.offheight);
    mjv_makeScene(model, scene_.get(), model->ngeom + 64);
    // Textures (filled procedurally by World) are uploaded here.
    mjr_makeContext(model, context_.get(), mjFONTSCALE_100);
    mjr_setBuffer(mjFB_OFFSCREEN, context_.get());
    if (context_->currentBuffer != mjFB_OFFSCREEN) {
      throw MujocoError("MuJoCo: the offscreen framebuffer is not available on this GL context");
    }
  } catch (const MujocoError& error) {
    mjr_freeContext(context_.get());
    mjv_freeScene(scene_.get());
    mj_deleteData(data_);
    // "Offscreen framebuffer is not complete" under a memory limit is the limit.
    const std::string limit_note = address_space_limit_note();
    if (limit_note.empty()) throw;
    throw OutOfMemory(error.what() + limit_note);
  } catch (...) {
    mjr_freeContext(context_.get());
    mjv_freeScene(scene_.get());
    mj_deleteData(data_);
    throw;
  }
  egl_.release();
  if (watchdog_) watchdog_->disarm();
  near_m_ = model->vis.map.znear * model->stat.extent;
  far_m_ = model->vis.map.zfar * model->stat.extent;
}

Renderer::~Renderer() {
  // Under an address-space limit llvmpipe's teardown can wait forever for a thread it could not
  // start, as its start-up can (a run that failed to assemble then hung instead of saying so).
  const RenderStallWatchdog::Scope watched(watchdog_.get(), "freeing the renderer");
  egl_.make_current();
  mjr_freeContext(context_.get());
  mjv_freeScene(scene_.get());
  mj_deleteData(data_);
}

int Renderer::overview_camera_id() const {
  return mj_name2id(world_.model(), mjOBJ_CAMERA, kOverviewCameraName);
}

void Renderer::set_state(const WorldSnapshot& snapshot) noexcept {
  const mjModel* model = world_.model();
  snapshot.restore(model, data_);
  mj_kinematics(model, data_);
  mj_camlight(model, data_);
  state_step_ = snapshot.step;
  state_stamp_ns_ = snapshot.stamp_ns;
  has_state_ = true;
}

void Renderer::apply_view(const ViewOptions& view) {
  for (int group = 0; group < mjNGROUP; ++group) {
    option_->geomgroup[group] = group <= 2 ? 1 : 0;
    option_->sitegroup[group] = 0;  // Sites are markers for the sim, never seen.
  }
  option_->geomgroup[kHiddenFromEyesGeomGroup] = view.show_head ? 1 : 0;
  option_->geomgroup[kEyeSkyGeomGroup] = view.skybox ? 0 : 1;
  scene_->flags[mjRND_SHADOW] = view.shadows ? 1 : 0;
  scene_->flags[mjRND_REFLECTION] = view.reflections ? 1 : 0;
  scene_->flags[mjRND_SKYBOX] = view.skybox ? 1 : 0;
  set_texture_filter(view.trilinear_textures);
}

void Renderer::set_texture_filter(bool trilinear) {
  if (trilinear == textures_trilinear_) return;
  const GLint filter = trilinear ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR_MIPMAP_NEAREST;
  for (int i = 0; i < context_->ntexture; ++i) {
    const GLenum target =
        context_->textureType[i] == mjTEXTURE_2D ? GL_TEXTURE_2D : GL_TEXTURE_CUBE_MAP;
    glBindTexture(target, context_->texture[i]);
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, filter);
  }
  textures_trilinear_ = trilinear;
}

bool Renderer::render(int camera_id, int width_px, int height_px, const ViewOptions& view,
                      std::uint8_t* rgb, float* depth) noexcept {
  return render(camera_id, ImageWindow::whole(width_px, height_px), view, rgb, depth);
}

bool Renderer::render(int camera_id, const ImageWindow& window, const ViewOptions& view,
                      std::uint8_t* rgb, float* depth) noexcept {
  const int width_px = window.width_px;
  const int height_px = window.height_px;
  const RenderStallWatchdog::Scope watched(watchdog_.get(), "rendering");
  try {
    egl_.make_current();
    const mjModel* model = world_.model();
    mjvCamera camera;
    mjv_defaultCamera(&camera);
    camera.type = mjCAMERA_FIXED;
    camera.fixedcamid = camera_id;
    apply_view(view);
    mjv_updateScene(model, data_, option_.get(), nullptr, &camera, mjCAT_ALL, scene_.get());
    if (!window.is_whole()) {
      // Mono rendering draws through the average of the scene's two GL cameras: narrow both.
      narrow_frustum(scene_->camera[0], window);
      narrow_frustum(scene_->camera[1], window);
    }
    if (!view.shadows && !view.reflections) {
      cull_and_order_for_view(scene_.get(), static_cast<double>(width_px) / height_px);
    }
    const mjrRect viewport{0, 0, width_px, height_px};
    mjr_render(viewport, scene_.get(), context_.get());
    mjr_readPixels(rgb, depth, viewport, context_.get());
    // The loops that render (camera loop, ground truth) may run on different threads; a GL
    // context is bound to one thread at a time, so it is handed back after every view.
    egl_.release();
    if (depth != nullptr) {
      // OpenGL depth d in [0, 1] of a perspective projection with planes n and f; the metric
      // depth along the optical axis is z = n f / (f - d (f - n)).
      const double n = near_m_;
      const double f = far_m_;
      const std::size_t count =
          static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px);
      for (std::size_t i = 0; i < count; ++i) {
        depth[i] = static_cast<float>(n * f / (f - static_cast<double>(depth[i]) * (f - n)));
      }
    }
    return true;
  } catch (...) {
    egl_.release();
    return false;
  }
}

void Renderer::render_raw_reference(int camera_id, int width_px, int height_px, std::uint8_t* rgb) {
  const RenderStallWatchdog::Scope watched(watchdog_.get(), "rendering");
  egl_.make_current();
  const mjModel* model = world_.model();
  mjvCamera camera;
  mjv_defaultCamera(&camera);
  camera.type = mjCAMERA_FIXED;
  camera.fixedcamid = camera_id;
  apply_view(ViewOptions{});
  mjv_updateScene(model, data_, option_.get(), nullptr, &camera, mjCAT_ALL, scene_.get());
  const mjrRect viewport{0, 0, width_px, height_px};
  mjr_render(viewport, scene_.get(), context_.get());
  mjr_readPixels(rgb, nullptr, viewport, context_.get());
  egl_.release();
}

}  // namespace cambio::sim
