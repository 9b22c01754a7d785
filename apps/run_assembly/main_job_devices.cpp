#include "main_job.hpp"

#include <iostream>
#include <stdexcept>

#include "cambio/sim/ground_truth.hpp"
#include "cambio/sim/rendered_views.hpp"

// MainJob's backends, the devices they make, and what they offer besides devices.

namespace cambio::app {

void MainJob::build_backends(const hal::BackendFactory& factory) {
  const hal::BackendContext context{&executor_->clock(), experiment_.seed, realtime_};
  for (const auto& camera : hardware_.cameras) {
    cameras_.push_back(backend_for(factory, context, camera.backend, "camera '" + camera.name + "'")
                           .make_camera(camera.name));
  }
  for (const auto& group : hardware_.groups) {
    groups_.push_back(
        backend_for(factory, context, group.backend, "joint group '" + group.name + "'")
            .make_joint_group(group.name));
    joint_order_.insert(joint_order_.end(), group.joints.begin(), group.joints.end());
  }
  if (backends_.empty()) throw std::runtime_error("the rig names no joint group and no camera");
  follow_driven_groups();
  if (experiment_.task == config::ControlTask::kGaze) make_touch_sensors(factory, context);
  for (auto& [name, backend] : backends_) backend->configure();
  for (auto& [name, backend] : backends_) backend->offer(offers_);
}

hal::Backend& MainJob::backend_for(const hal::BackendFactory& factory,
                                   const hal::BackendContext& context, const std::string& name,
                                   const std::string& requested_by) {
  // One backend instance per backend name, shared by every device naming it.
  auto& slot = backends_[name];
  if (!slot) slot = factory.make(name, hardware_, context, requested_by);
  return *slot;
}

void MainJob::follow_driven_groups() {
  for (auto& group : groups_) driven_groups_.push_back(group.get());
  for (auto& [follower_name, follower] : backends_) {
    follow_groups_of_other_backends(follower_name, *follower);
  }
}

void MainJob::follow_groups_of_other_backends(const std::string& follower_name,
                                              hal::Backend& follower) {
  // A backend that models the whole robot (the sim) follows every group another backend
  // drives, so its cameras see what those drives did.
  if (!follower.follows_other_backends()) return;
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    if (hardware_.groups[g].backend == follower_name) continue;
    taps_.push_back(std::make_unique<hal::JointStateTap>(*driven_groups_[g]));
    follower.follow_group(hardware_.groups[g], *taps_.back());
    driven_groups_[g] = taps_.back().get();
  }
}

void MainJob::make_touch_sensors(const hal::BackendFactory& factory,
                                 const hal::BackendContext& context) {
  // An arm reaches when its group is shaped as control::ArmChain and its gripper carries a touch
  // sensor; its side is where its shoulder is (y > 0: left).
  for (const auto& sensor : hardware_.touch_sensors) {
    const hal::JointInfo* gripper = hardware_.find_joint(sensor.parent);
    if (gripper == nullptr) continue;
    control::ArmChain chain;
    try {
      chain = control::find_arm_chain(hardware_, gripper->group);
    } catch (const std::invalid_argument& error) {
      std::cerr << "cambio: warning: touch sensor '" << sensor.name << "': " << error.what()
                << "; that arm does not reach\n";
      continue;
    }
    if (chain.names[4] != sensor.parent) continue;
    const std::size_t side = chain.shoulder_W.y() > 0.0 ? 0 : 1;
    if (touch_sensors_[side]) continue;
    // A backend no group or camera names is made here, like theirs; made after the others
    // followed the driven groups, it follows them now (configure() checks what it moves).
    const bool made_here = !backends_.contains(sensor.backend);
    hal::Backend& backend =
        backend_for(factory, context, sensor.backend, "touch sensor '" + sensor.name + "'");
    if (made_here) follow_groups_of_other_backends(sensor.backend, backend);
    touch_sensors_[side] = backend.make_touch_sensor(sensor.name);
    arm_groups_[side] = gripper->group;
  }
}

sim::GroundTruth* MainJob::ground_truth() {
  return offers_.find<sim::GroundTruth>();
}

std::optional<sim::RendererDescription> MainJob::renderer() const {
  for (const sim::RenderedViews* views : offers_.all<sim::RenderedViews>()) {
    if (auto description = views->renderer()) return description;
  }
  return std::nullopt;
}

}  // namespace cambio::app
