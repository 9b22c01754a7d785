#include "cambio/sim/ground_truth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <mujoco/mujoco.h>

#include "cambio/sim/mjcf_builder.hpp"
#include "cambio/sim/mujoco_error.hpp"
#include "sim_camera.hpp"
#include "sim_lens.hpp"

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

namespace {

/// Signed distance from `p_W` to the nearest geom of `body` (see distance_to_object_m);
/// `colliding_only` skips geoms that collide with nothing (a joint's collar).
double body_distance_m(const mjModel* model, const mjData* data, int body,
                       const Eigen::Vector3d& p_W, const std::string& object_name,
                       bool colliding_only = false) {
  double nearest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < model->ngeom; ++i) {
    if (model->geom_bodyid[i] != body) continue;
    if (colliding_only && model->geom_contype[i] == 0 && model->geom_conaffinity[i] == 0) continue;
    const Eigen::Isometry3d X_WG = pose_from(data->geom_xpos + 3 * i, data->geom_xmat + 9 * i);
    const Eigen::Vector3d p = X_WG.inverse() * p_W;
    const mjtNum* size = model->geom_size + 3 * i;
    double d = 0.0;
    switch (model->geom_type[i]) {
      case mjGEOM_SPHERE:
        d = p.norm() - size[0];
        break;
      case mjGEOM_ELLIPSOID:
        d = p.norm() - std::max({size[0], size[1], size[2]});
        break;
      case mjGEOM_BOX: {
        // The exact signed distance to a box of half-sizes `size`.
        const Eigen::Vector3d q = p.cwiseAbs() - Eigen::Vector3d(size[0], size[1], size[2]);
        d = q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
        break;
      }
      case mjGEOM_CYLINDER: {
        const Eigen::Vector2d q(std::hypot(p.x(), p.y()) - size[0], std::abs(p.z()) - size[1]);
        d = q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
        break;
      }
      case mjGEOM_CAPSULE: {
        const double z = std::clamp(p.z(), -size[1], size[1]);
        d = (p - Eigen::Vector3d(0.0, 0.0, z)).norm() - size[0];
        break;
      }
      default:
        throw std::invalid_argument("object '" + object_name +
                                    "' has a geom whose distance is not computed here");
    }
    nearest = std::min(nearest, d);
  }
  return nearest;
}

}  // namespace

int GroundTruth::object_body(const std::string& object_name) const {
  for (const auto& object : world_.objects()) {
    if (object.name == object_name) return object.body_id;
  }
  throw std::out_of_range("no object named '" + object_name + "' in the scene");
}

double GroundTruth::distance_to_object_m(const std::string& object_name,
                                         const Eigen::Vector3d& p_W) {
  const int body = object_body(object_name);
  refresh();
  std::lock_guard<std::mutex> lock(mutex_);
  return body_distance_m(world_.model(), data_, body, p_W, object_name);
}

double GroundTruth::end_effector_gap_m(const std::string& link_name,
                                       const std::string& object_name) {
  const int object = object_body(object_name);
  const std::vector<int> hand = world_.end_effector_bodies(link_name);
  refresh();
  std::lock_guard<std::mutex> lock(mutex_);
  const mjModel* model = world_.model();
  // Between two convex shapes the nearest points are a vertex or an edge of one and a face or an
  // edge of the other: points along each side's edges (and axes) are measured against the other
  // side, to within the spacing of the points where two edges cross.
  const auto colliding = [&](int geom) {
    return model->geom_contype[geom] != 0 || model->geom_conaffinity[geom] != 0;
  };
  const auto vertices = [&](const std::vector<int>& bodies, const auto& measure) {
    for (int i = 0; i < model->ngeom; ++i) {
      if (std::find(bodies.begin(), bodies.end(), model->geom_bodyid[i]) == bodies.end() ||
          !colliding(i)) {
        continue;
      }
      const Eigen::Isometry3d X_WG = pose_from(data_->geom_xpos + 3 * i, data_->geom_xmat + 9 * i);
      const mjtNum* size = model->geom_size + 3 * i;
      switch (model->geom_type[i]) {
        case mjGEOM_BOX:
          // Points along the twelve edges (corners included): an edge meeting an edge is as
          // common as a corner meeting a face when a tilted finger meets a box.
          for (int axis = 0; axis < 3; ++axis) {
            for (int edge = 0; edge < 4; ++edge) {
              for (int k = 0; k <= 8; ++k) {
                Eigen::Vector3d p;
                p[axis] = size[axis] * (k / 4.0 - 1.0);
                p[(axis + 1) % 3] = (edge & 1 ? 1 : -1) * size[(axis + 1) % 3];
                p[(axis + 2) % 3] = (edge & 2 ? 1 : -1) * size[(axis + 2) % 3];
                measure(X_WG * p, 0.0);
              }
            }
          }
          break;
        case mjGEOM_CAPSULE:
        case mjGEOM_CYLINDER:
          for (int k = 0; k <= 8; ++k) {
            measure(X_WG * Eigen::Vector3d(0.0, 0.0, size[1] * (k / 4.0 - 1.0)), size[0]);
          }
          break;
        default:
          measure(X_WG.translation(), size[0]);
          break;
      }
    }
  };
  double gap = std::numeric_limits<double>::infinity();
  vertices(hand, [&](const Eigen::Vector3d& p_W, double less_m) {
    gap = std::min(gap, body_distance_m(model, data_, object, p_W, object_name) - less_m);
  });
  const std::vector<int> object_bodies{object};
  vertices(object_bodies, [&](const Eigen::Vector3d& p_W, double less_m) {
    for (const int body : hand) {
      gap = std::min(gap, body_distance_m(model, data_, body, p_W, link_name, true) - less_m);
    }
  });
  return gap;
}

RayHit GroundTruth::cast_ray(const Eigen::Vector3d& p_W, const Eigen::Vector3d& direction_W,
                             std::string_view ignore_object) {
  const double length = direction_W.norm();
  if (!(length > 0.0) || !std::isfinite(length) || !p_W.allFinite()) {
    throw std::invalid_argument("a ray needs a finite origin and a non-zero, finite direction");
  }
  int exclude_body = -1;
  int exclude_geom = -1;
  if (!ignore_object.empty()) {
    for (const auto& object : world_.objects()) {
      if (object.name == ignore_object) exclude_body = object.body_id;
    }
    if (exclude_body < 0) {
      // Scene geometry that is no object (the floor), as RayHit::object names it.
      const std::string name(ignore_object);
      exclude_geom = mj_name2id(world_.model(), mjOBJ_GEOM, name.c_str());
      if (exclude_geom < 0 || world_.model()->geom_group[exclude_geom] != kSceneGeomGroup) {
        throw std::out_of_range("no object named '" + name + "' in the scene");
      }
    }
  }
  const Eigen::Vector3d unit = direction_W / length;
  refresh();
  std::lock_guard<std::mutex> lock(mutex_);
  const mjModel* model = world_.model();
  // Scene geoms only: the robot's are in kRobotGeomGroup / kHiddenFromEyesGeomGroup and the
  // eyes' sky planes in kEyeSkyGeomGroup (mjcf_builder.cpp). mj_ray's group filter cannot say
  // this: MuJoCo 2.2 lets every plane through it (the sky planes would stop every ray), so the
  // geoms are tested one by one with the same per-shape intersections mj_ray uses.
  int geom = -1;
  double distance = -1.0;
  for (int i = 0; i < model->ngeom; ++i) {
    if (model->geom_group[i] != kSceneGeomGroup || model->geom_bodyid[i] == exclude_body ||
        i == exclude_geom) {
      continue;
    }
    double d = -1.0;
    switch (model->geom_type[i]) {
      case mjGEOM_MESH:
        d = mj_rayMesh(model, data_, i, p_W.data(), unit.data());
        break;
      case mjGEOM_HFIELD:
        d = mj_rayHfield(model, data_, i, p_W.data(), unit.data());
        break;
      default:
        d = mju_rayGeom(data_->geom_xpos + 3 * i, data_->geom_xmat + 9 * i,
                        model->geom_size + 3 * i, p_W.data(), unit.data(), model->geom_type[i]);
        break;
    }
    if (d >= 0.0 && (geom < 0 || d < distance)) {
      geom = i;
      distance = d;
    }
  }
  RayHit result;
  if (distance < 0.0 || geom < 0) return result;
  result.hit = true;
  result.distance_m = distance;
  result.p_W = p_W + distance * unit;
  const int body = model->geom_bodyid[geom];
  for (const auto& object : world_.objects()) {
    if (object.body_id == body) result.object = object.name;
  }
  if (result.object.empty()) {
    const char* name = mj_id2name(model, mjOBJ_GEOM, geom);
    if (name != nullptr) result.object = name;
  }
  return result;
}

RayHit GroundTruth::segment_blocker(const Eigen::Vector3d& p_from_W, const Eigen::Vector3d& p_to_W,
                                    std::string_view ignore_object, double tolerance_m) {
  const Eigen::Vector3d segment = p_to_W - p_from_W;
  const double length = segment.norm();
  if (!(length > tolerance_m)) return {};
  RayHit hit = cast_ray(p_from_W, segment, ignore_object);
  if (hit.hit && hit.distance_m < length - tolerance_m) return hit;
  return {};
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

void GroundTruth::render_as_seen(const std::string& camera_name, hal::Image& rgb) {
  const config::CameraConfig* camera = world_.rig().find_camera(camera_name);
  if (camera == nullptr || camera->backend != "sim" || camera->distortion.is_zero()) {
    render(camera_name, 0, 0, ViewOptions{}, rgb, nullptr);
    return;
  }
  if (!renderer_provider_) throw std::logic_error("ground truth rendering needs the sim renderer");
  std::shared_ptr<const SimLens>& lens = lenses_[camera_name];
  if (!lens) {
    hal::CameraInfo info;
    info.name = camera_name;
    info.intrinsics = {camera->width_px,   camera->height_px,      camera->focal_x_px,
                       camera->focal_y_px, camera->principal_x_px, camera->principal_y_px};
    info.distortion = camera->distortion;
    lens = std::make_shared<const SimLens>(info);
  }
  Renderer& renderer = renderer_provider_();
  rgb_bottom_up_.resize(lens->ideal_bytes());
  refresh();
  {
    const Renderer::Lease lease(renderer, Renderer::Lease::Mode::kWait);
    std::lock_guard<std::mutex> lock(mutex_);
    renderer.set_state(current_);
    if (!renderer.render(world_.camera_id(camera_name), lens->window(), ViewOptions{},
                         rgb_bottom_up_.data(), nullptr)) {
      throw MujocoError("MuJoCo could not render '" + camera_name + "'");
    }
    rgb.stamp_ns = current_.stamp_ns;
  }
  rgb.resize(camera->width_px, camera->height_px, hal::PixelFormat::kRgb8);
  lens->apply(rgb_bottom_up_.data(), rgb);
}

}  // namespace cambio::sim
