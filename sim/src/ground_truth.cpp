#include "cambio/sim/ground_truth.hpp"

#include <stdexcept>

#include <mujoco/mujoco.h>

#include "cambio/sim/mujoco_error.hpp"
#include "sim_camera.hpp"

namespace cambio::sim {

namespace {

Eigen::Isometry3d pose_from(const mjtNum* xpos, const mjtNum* xmat) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(xpos[0], xpos[1], xpos[2]);
  X.linear() = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(xmat);
  return X;
}

}  // namespace

GroundTruth::GroundTruth(const World& world, hal::TripleBuffer<WorldSnapshot>& truth_snapshots)
    : world_(world), snapshots_(truth_snapshots) {
  data_ = mj_makeData(world_.model());
  if (data_ == nullptr) throw MujocoError("MuJoCo: could not allocate the ground truth's mjData");
  mj_copyData(data_, world_.model(), world_.data());
  mj_kinematics(world_.model(), data_);
  mj_camlight(world_.model(), data_);
  current_.resize_for(world_.model());
  current_.capture(world_.model(), world_.data(), 0, 0);
}

GroundTruth::~GroundTruth() {
  mj_deleteData(data_);
}

void GroundTruth::refresh() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!snapshots_.acquire()) return;
  // Same-sized vectors: the copy does not allocate.
  current_ = snapshots_.front();
  current_.restore(world_.model(), data_);
  mj_kinematics(world_.model(), data_);
  mj_camlight(world_.model(), data_);
}

std::int64_t GroundTruth::stamp_ns() {
  refresh();
  return current_.stamp_ns;
}

std::uint64_t GroundTruth::step() {
  refresh();
  return current_.step;
}

double GroundTruth::joint_position_rad(const std::string& joint_name) {
  refresh();
  const int index = world_.find_joint(joint_name);
  if (index < 0) throw std::out_of_range("no joint named '" + joint_name + "' in the sim world");
  return data_->qpos[world_.joints()[static_cast<std::size_t>(index)].qpos_address];
}

Eigen::Isometry3d GroundTruth::X_WC(const std::string& camera_name) {
  refresh();
  const int id = world_.camera_id(camera_name);
  Eigen::Isometry3d X_W_mujoco = pose_from(data_->cam_xpos + 3 * id, data_->cam_xmat + 9 * id);
  // MuJoCo's camera frame looks down -z with y up; the optical frame is it turned half a turn
  // about x.
  X_W_mujoco.linear() = X_W_mujoco.linear() * Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
  return X_W_mujoco;
}

Eigen::Isometry3d GroundTruth::X_WO(const std::string& object_name) {
  refresh();
  for (const auto& object : world_.objects()) {
    if (object.name == object_name) {
      return pose_from(data_->xpos + 3 * object.body_id, data_->xmat + 9 * object.body_id);
    }
  }
  throw std::out_of_range("no object named '" + object_name + "' in the scene");
}

Eigen::Isometry3d GroundTruth::X_WL(const std::string& link_name) {
  refresh();
  const int body =
      link_name == "base" ? 0 : mj_name2id(world_.model(), mjOBJ_BODY, link_name.c_str());
  if (body < 0) throw std::out_of_range("no link named '" + link_name + "' in the sim world");
  return pose_from(data_->xpos + 3 * body, data_->xmat + 9 * body);
}

void GroundTruth::render(const std::string& camera_name, int width_px, int height_px,
                         const ViewOptions& view, hal::Image& rgb, std::vector<float>* depth_m) {
  if (!renderer_provider_) throw std::logic_error("ground truth rendering needs the sim renderer");
  Renderer& renderer = renderer_provider_();
  const int id = world_.camera_id(camera_name);
  if (width_px <= 0 || height_px <= 0) {
    const config::CameraConfig* camera = world_.rig().find_camera(camera_name);
    if (camera == nullptr) throw std::invalid_argument("'" + camera_name + "' needs a size");
    width_px = camera->width_px;
    height_px = camera->height_px;
  }
  const int max_width = world_.model()->vis.global.offwidth;
  const int max_height = world_.model()->vis.global.offheight;
  if (width_px > max_width || height_px > max_height) {
    throw std::invalid_argument("a " + std::to_string(width_px) + "x" + std::to_string(height_px) +
                                " view does not fit the offscreen buffer (" +
                                std::to_string(max_width) + "x" + std::to_string(max_height) +
                                "); raise MjcfOptions::offscreen_*");
  }
  const std::size_t pixels =
      static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px);
  rgb_bottom_up_.resize(pixels * 3);
  if (depth_m != nullptr) depth_bottom_up_.resize(pixels);
  refresh();
  {
    // Not a loop: it may wait for a camera to finish with the renderer.
    const Renderer::Lease lease(renderer, Renderer::Lease::Mode::kWait);
    std::lock_guard<std::mutex> lock(mutex_);
    renderer.set_state(current_);
    if (!renderer.render(id, width_px, height_px, view, rgb_bottom_up_.data(),
                         depth_m != nullptr ? depth_bottom_up_.data() : nullptr)) {
      throw MujocoError("MuJoCo could not render '" + camera_name + "'");
    }
    rgb.stamp_ns = current_.stamp_ns;
  }
  rgb.resize(width_px, height_px, hal::PixelFormat::kRgb8);
  SimCamera::convert_rows(rgb_bottom_up_.data(), width_px, height_px, hal::PixelFormat::kRgb8, rgb);
  if (depth_m != nullptr) {
    depth_m->resize(pixels);
    for (int y = 0; y < height_px; ++y) {
      std::copy_n(depth_bottom_up_.data() + static_cast<std::size_t>(height_px - 1 - y) * width_px,
                  width_px, depth_m->data() + static_cast<std::size_t>(y) * width_px);
    }
  }
}

}  // namespace cambio::sim
