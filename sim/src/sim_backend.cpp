#include "cambio/sim/sim_backend.hpp"

#include <stdexcept>

#include "camera_frames.hpp"
#include "sim_camera.hpp"
#include "sim_joint_group.hpp"
#include "sim_touch_sensor.hpp"

namespace cambio::sim {

namespace {

std::string in_quotes(std::string_view name) {
  return "'" + std::string(name) + "'";
}

/// The sim's cameras for people: the renderer in use, and a foveated eye's view whole.
class SimRenderedViews final : public RenderedViews {
 public:
  SimRenderedViews(const config::RigConfig& rig, const std::unique_ptr<Renderer>& renderer,
                   GroundTruth& truth)
      : rig_(rig), renderer_(renderer), truth_(truth) {}

  std::optional<RendererDescription> renderer() const override {
    if (renderer_ == nullptr) return std::nullopt;
    return renderer_->description();
  }

  bool render_whole_frame(std::string_view camera_name, hal::Image& rgb) override {
    const config::CameraConfig* camera = rig_.find_camera(std::string(camera_name));
    if (camera == nullptr || camera->backend != SimBackend::kName ||
        !camera->sim_foveation.enabled()) {
      return false;
    }
    truth_.render(camera->name, 0, 0, ViewOptions{}, rgb, nullptr);
    return true;
  }

 private:
  const config::RigConfig& rig_;
  const std::unique_ptr<Renderer>& renderer_;  // The backend's, made on first use.
  GroundTruth& truth_;
};

}  // namespace

void register_sim_backend(hal::BackendFactory& factory, const config::RigConfig& rig,
                          config::SceneConfig scene) {
  factory.register_backend(SimBackend::kName,
                           [rig, scene = std::move(scene)](const hal::HardwareInfo& hardware,
                                                           const hal::BackendContext& context) {
                             return std::unique_ptr<hal::Backend>(
                                 std::make_unique<SimBackend>(rig, scene, hardware, context));
                           });
}

SimBackend::SimBackend(const config::RigConfig& rig, const config::SceneConfig& scene,
                       const hal::HardwareInfo& hardware, const hal::BackendContext& context,
                       const MjcfOptions& mjcf_options)
    : rig_(rig), hardware_(hardware), seed_(context.seed) {
  if (context.clock == nullptr) {
    throw std::invalid_argument("sim: no clock given (BackendContext::clock)");
  }
  world_ = std::make_unique<World>(rig_, scene, mjcf_options);
  for (const auto& joint : hardware_.joints) {
    if (world_->find_joint(joint.name) < 0) {
      throw std::invalid_argument("sim: the hardware description names joint " +
                                  in_quotes(joint.name) + ", which rig " + in_quotes(rig_.name) +
                                  " does not have");
    }
  }
  physics_ = std::make_unique<PhysicsLoop>(*world_, *context.clock, seed_);
  camera_frames_ = std::make_unique<CameraFrames>(physics_->render_snapshots());
  ground_truth_ = std::make_unique<GroundTruth>(*world_, physics_->truth_snapshots());
  ground_truth_->set_renderer_provider([this]() -> Renderer& { return renderer(); });
}

SimBackend::~SimBackend() = default;

std::unique_ptr<hal::JointGroup> SimBackend::make_joint_group(std::string_view group_name) {
  const hal::JointGroupInfo* group = hardware_.find_group(group_name);
  if (group == nullptr) {
    throw std::runtime_error("sim: the rig has no joint group " + in_quotes(group_name));
  }
  if (followed_groups_.count(group_name) != 0) {
    throw hal::BackendUnavailable("sim: joint group " + in_quotes(group_name) +
                                  " is driven by backend " + in_quotes(group->backend) +
                                  " and followed by the sim; it cannot also be a sim group");
  }
  if (group->backend != kName) {
    throw hal::BackendUnavailable("sim: joint group " + in_quotes(group_name) + " names backend " +
                                  in_quotes(group->backend) +
                                  ", not 'sim' (the sim can only follow it: follow_group)");
  }
  if (group->joints.size() > kMaxJointsPerGroup) {
    throw std::runtime_error("sim: joint group " + in_quotes(group_name) + " has " +
                             std::to_string(group->joints.size()) + " joints; at most " +
                             std::to_string(kMaxJointsPerGroup) + " are supported");
  }
  if (made_groups_.count(group_name) != 0) {
    throw std::runtime_error("sim: joint group " + in_quotes(group_name) +
                             " was already made (one writer per group)");
  }
  std::vector<int> indices;
  for (const auto& joint_name : group->joints) {
    const int index = world_->find_joint(joint_name);
    if (index < 0) {
      throw std::runtime_error("sim: joint group " + in_quotes(group_name) +
                               " names unknown joint " + in_quotes(joint_name));
    }
    indices.push_back(index);
  }
  GroupLink& link = physics_->add_group(group->name, indices);
  made_groups_.insert(group->name);
  return std::make_unique<SimJointGroup>(*group, link);
}

void SimBackend::follow_group(const hal::JointGroupInfo& group,
                              const hal::JointStateSource& leader) {
  const hal::JointGroupInfo* known = hardware_.find_group(group.name);
  if (known == nullptr) {
    throw hal::BackendUnavailable("sim: cannot follow joint group " + in_quotes(group.name) +
                                  ": the rig has no such group");
  }
  if (made_groups_.count(group.name) != 0 || known->backend == kName) {
    throw hal::BackendUnavailable("sim: cannot follow joint group " + in_quotes(group.name) +
                                  ": the sim drives it itself (backend 'sim'); only a group "
                                  "another backend drives can be followed");
  }
  if (followed_groups_.count(group.name) != 0) {
    throw hal::BackendUnavailable("sim: joint group " + in_quotes(group.name) +
                                  " is already followed (one leader per group)");
  }
  if (group.joints.size() > hal::JointStateSource::kMaxJoints) {
    throw hal::BackendUnavailable("sim: cannot follow joint group " + in_quotes(group.name) +
                                  ": more than " +
                                  std::to_string(hal::JointStateSource::kMaxJoints) + " joints");
  }
  std::vector<int> indices;
  for (const auto& joint_name : group.joints) {
    const int index = world_->find_joint(joint_name);
    if (index < 0) {
      throw hal::BackendUnavailable("sim: cannot follow joint group " + in_quotes(group.name) +
                                    ": its joint " + in_quotes(joint_name) +
                                    " is not in the sim world");
    }
    indices.push_back(index);
  }
  physics_->add_follower(group.name, indices, leader);
  followed_groups_.insert(group.name);
}

std::unique_ptr<hal::Camera> SimBackend::make_camera(std::string_view camera_name) {
  const hal::CameraInfo* camera = hardware_.find_camera(camera_name);
  const config::CameraConfig* config = rig_.find_camera(std::string(camera_name));
  if (camera == nullptr || config == nullptr) {
    throw std::runtime_error("sim: the rig has no camera " + in_quotes(camera_name));
  }
  if (camera->backend != kName) {
    throw hal::BackendUnavailable("sim: camera " + in_quotes(camera_name) + " names backend " +
                                  in_quotes(camera->backend) + ", not 'sim'");
  }
  if (made_cameras_.count(camera_name) != 0) {
    throw std::runtime_error("sim: camera " + in_quotes(camera_name) + " was already made");
  }
  // Noise streams after the servos' (one per joint).
  const std::uint64_t stream = 0x10000 + camera_streams_++;
  auto made = std::make_unique<SimCamera>(*camera, world_->camera_id(camera->name), renderer(),
                                          *camera_frames_, config->image_noise_std,
                                          seed_ * 0x100000001B3ULL + stream, config->sim_foveation);
  made_cameras_.insert(camera->name);
  return made;
}

std::unique_ptr<hal::TouchSensor> SimBackend::make_touch_sensor(std::string_view sensor_name) {
  for (const auto& sensor : hardware_.touch_sensors) {
    if (sensor.name != sensor_name) continue;
    if (sensor.backend != kName) {
      throw hal::BackendUnavailable("sim: touch sensor " + in_quotes(sensor_name) +
                                    " names backend " + in_quotes(sensor.backend) + ", not 'sim'");
    }
    if (made_touch_sensors_.count(sensor_name) != 0) {
      throw std::runtime_error("sim: touch sensor " + in_quotes(sensor_name) + " was already made");
    }
    TouchLink& link =
        physics_->add_touch_sensor(sensor.name, world_->end_effector_bodies(sensor.parent));
    made_touch_sensors_.insert(sensor.name);
    return std::make_unique<SimTouchSensor>(link);
  }
  throw std::runtime_error("sim: the rig has no touch sensor " + in_quotes(sensor_name));
}

void SimBackend::check_moved_by_sim(std::string_view device, const std::string& link) const {
  std::string current = link;
  // The hardware description refuses a parent chain that does not reach the base; the bound
  // only guards the walk.
  for (std::size_t hops = 0; current != "base" && hops <= hardware_.joints.size(); ++hops) {
    const hal::JointInfo* joint = hardware_.find_joint(current);
    if (joint == nullptr) return;
    const hal::JointGroupInfo* group = hardware_.find_group(joint->group);
    if (group != nullptr && group->backend != kName && followed_groups_.count(group->name) == 0) {
      throw std::runtime_error(
          "sim: " + std::string(device) + " hangs from joint " + in_quotes(joint->name) +
          " of joint group " + in_quotes(group->name) + ", which backend " +
          in_quotes(group->backend) +
          " drives and the sim does not follow, so the sim would never move it (follow the "
          "group: Backend::follow_group)");
    }
    current = joint->parent;
  }
}

void SimBackend::configure() {
  for (const auto& camera_name : made_cameras_) {
    check_moved_by_sim("camera " + in_quotes(camera_name),
                       hardware_.find_camera(camera_name)->parent_frame);
  }
  for (const auto& sensor : hardware_.touch_sensors) {
    if (made_touch_sensors_.count(sensor.name) == 0) continue;
    check_moved_by_sim("touch sensor " + in_quotes(sensor.name), sensor.parent);
  }
}

void SimBackend::activate() {
  physics_->activate();
}

void SimBackend::deactivate() noexcept {
  physics_->deactivate();
}

std::vector<hal::BackendLoop> SimBackend::loops() {
  int priority = 0;
  if (const config::LoopConfig* joint_loop = rig_.find_loop("joint"))
    priority = joint_loop->priority;
  return {hal::BackendLoop{physics_.get(), rig_.sim.physics_rate_hz, priority}};
}

int SimBackend::sim_joint(std::string_view joint_name) const {
  const hal::JointInfo* joint = hardware_.find_joint(joint_name);
  const hal::JointGroupInfo* group =
      joint != nullptr ? hardware_.find_group(joint->group) : nullptr;
  if (group == nullptr || group->backend != kName) {
    throw std::invalid_argument("sim: joint " + in_quotes(joint_name) +
                                " is not in a joint group the sim drives");
  }
  return world_->find_joint(joint_name);
}

void SimBackend::inject_fault(std::string_view joint_name, std::uint16_t emcy_error_code) {
  if (emcy_error_code == 0) {
    throw std::invalid_argument("sim: a fault needs an emergency error code (0 means none)");
  }
  physics_->inject_fault(sim_joint(joint_name), emcy_error_code);
}

void SimBackend::inject_comm_loss(std::string_view joint_name) {
  physics_->inject_comm_loss(sim_joint(joint_name));
}

void SimBackend::freeze_feedback(std::string_view joint_name, bool frozen) {
  physics_->freeze_feedback(sim_joint(joint_name), frozen);
}

Renderer& SimBackend::renderer() {
  if (!renderer_) renderer_ = std::make_unique<Renderer>(*world_);
  return *renderer_;
}

GroundTruth& SimBackend::ground_truth() {
  return *ground_truth_;
}

void SimBackend::offer(hal::BackendOffers& offers) {
  if (!rendered_views_) {
    rendered_views_ = std::make_unique<SimRenderedViews>(rig_, renderer_, *ground_truth_);
  }
  offers.offer<GroundTruth>(*ground_truth_);
  offers.offer<RenderedViews>(*rendered_views_);
}

}  // namespace cambio::sim
