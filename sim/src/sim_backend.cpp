#include "cambio/sim/sim_backend.hpp"

#include <stdexcept>

#include "cambio/config/scene_config.hpp"
#include "cambio/config/shipped_config.hpp"
#include "sim_camera.hpp"
#include "sim_joint_group.hpp"
#include "sim_touch_sensor.hpp"

namespace cambio::sim {

namespace {

std::string quoted(std::string_view name) {
  return "'" + std::string(name) + "'";
}

}  // namespace

void register_sim_backend(hal::BackendFactory& factory) {
  factory.register_backend(
      "sim", [](const config::RigConfig& rig, const hal::BackendOptions& options) {
        config::SceneConfig scene;
        if (!options.scene_path.empty()) {
          scene = config::load_scene(config::resolve_config_argument("scenes", options.scene_path));
        } else {
          scene.name = "empty";
        }
        return std::unique_ptr<hal::Backend>(std::make_unique<SimBackend>(rig, scene, options));
      });
}

SimBackend::SimBackend(const config::RigConfig& rig, const config::SceneConfig& scene,
                       const hal::BackendOptions& options, const MjcfOptions& mjcf_options)
    : rig_(rig), options_(options) {
  world_ = std::make_unique<World>(rig_, scene, mjcf_options);
  physics_ = std::make_unique<PhysicsLoop>(*world_, options_.seed);
  ground_truth_ = std::make_unique<GroundTruth>(*world_, physics_->truth_snapshots());
  ground_truth_->set_renderer_provider([this]() -> Renderer& { return renderer(); },
                                       &physics_->render_snapshots());
}

SimBackend::~SimBackend() = default;

std::unique_ptr<hal::JointGroup> SimBackend::make_joint_group(std::string_view group_name) {
  const config::JointGroupConfig* group = rig_.find_group(std::string(group_name));
  if (group == nullptr) {
    throw std::runtime_error("sim: the rig has no joint group " + quoted(group_name));
  }
  if (group->backend != "sim") {
    throw std::runtime_error("sim: joint group " + quoted(group_name) + " names backend '" +
                             group->backend + "', not 'sim'");
  }
  if (group->joints.size() > kMaxJointsPerGroup) {
    throw std::runtime_error("sim: joint group " + quoted(group_name) + " has " +
                             std::to_string(group->joints.size()) + " joints; at most " +
                             std::to_string(kMaxJointsPerGroup) + " are supported");
  }
  if (!made_groups_.insert(std::string(group_name)).second) {
    throw std::runtime_error("sim: joint group " + quoted(group_name) +
                             " was already made (one writer per group)");
  }
  hal::JointGroupInfo info;
  info.name = group->name;
  info.backend = "sim";
  std::vector<int> indices;
  for (const auto& joint_name : group->joints) {
    const int index = world_->find_joint(joint_name);
    const config::JointConfig* joint = rig_.find_joint(joint_name);
    if (index < 0 || joint == nullptr) {
      throw std::runtime_error("sim: joint group " + quoted(group_name) + " names unknown joint " +
                               quoted(joint_name));
    }
    indices.push_back(index);
    info.joints.push_back(joint_name);
    info.limits.push_back({joint->min_position_rad, joint->max_position_rad,
                           joint->max_velocity_rad_s, joint->max_acceleration_rad_s2,
                           joint->max_effort_nm});
  }
  GroupLink& link = physics_->add_group(group->name, indices);
  // Readings exist before the first physics step.
  physics_->activate();
  return std::make_unique<SimJointGroup>(std::move(info), link);
}

std::unique_ptr<hal::Camera> SimBackend::make_camera(std::string_view camera_name) {
  const config::CameraConfig* camera = rig_.find_camera(std::string(camera_name));
  if (camera == nullptr)
    throw std::runtime_error("sim: the rig has no camera " + quoted(camera_name));
  if (camera->backend != "sim") {
    throw std::runtime_error("sim: camera " + quoted(camera_name) + " names backend '" +
                             camera->backend + "', not 'sim'");
  }
  if (!made_cameras_.insert(std::string(camera_name)).second) {
    throw std::runtime_error("sim: camera " + quoted(camera_name) + " was already made");
  }
  hal::CameraInfo info;
  info.name = camera->name;
  info.frame_name = camera->parent;
  info.intrinsics = {camera->width_px,   camera->height_px,      camera->focal_x_px,
                     camera->focal_y_px, camera->principal_x_px, camera->principal_y_px};
  info.format = camera->format == config::PixelFormatConfig::kGrey8 ? hal::PixelFormat::kGrey8
                                                                    : hal::PixelFormat::kRgb8;
  if (const config::LoopConfig* loop = rig_.find_loop("camera")) info.rate_hz = loop->rate_hz;
  // Noise streams after the servos' (one per joint).
  const std::uint64_t stream = 0x10000 + camera_streams_++;
  return std::make_unique<SimCamera>(std::move(info), world_->camera_id(camera->name), renderer(),
                                     physics_->render_snapshots(), camera->image_noise_std,
                                     options_.seed * 0x100000001B3ULL + stream);
}

std::unique_ptr<hal::TouchSensor> SimBackend::make_touch_sensor(std::string_view sensor_name) {
  for (const auto& sensor : rig_.touch_sensors) {
    if (sensor.name != sensor_name) continue;
    TouchLink& link =
        physics_->add_touch_sensor(sensor.name, world_->end_effector_bodies(sensor.parent));
    physics_->activate();
    return std::make_unique<SimTouchSensor>(link);
  }
  throw std::runtime_error("sim: the rig has no touch sensor " + quoted(sensor_name));
}

hal::Clock& SimBackend::clock() {
  if (options_.realtime) return monotonic_clock_;
  return manual_clock_;
}

std::vector<hal::BackendLoop> SimBackend::loops() {
  int priority = 0;
  if (const config::LoopConfig* joint_loop = rig_.find_loop("joint"))
    priority = joint_loop->priority;
  return {hal::BackendLoop{physics_.get(), rig_.sim.physics_rate_hz, priority}};
}

Renderer& SimBackend::renderer() {
  if (!renderer_) renderer_ = std::make_unique<Renderer>(*world_);
  return *renderer_;
}

GroundTruth& SimBackend::ground_truth() {
  return *ground_truth_;
}

}  // namespace cambio::sim
