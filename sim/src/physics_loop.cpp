#include "cambio/sim/physics_loop.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include <mujoco/mujoco.h>

#include "cambio/sim/object_motion.hpp"

namespace cambio::sim {

namespace {

// Closed-loop bandwidth and damping of the physics joints' position servo.
constexpr double kDriveBandwidthHz = 10.0;
constexpr double kDriveDampingRatio = 1.0;

// Distinct, reproducible seeds per noise source from one run seed (splitmix64).
std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

}  // namespace

PhysicsLoop::PhysicsLoop(World& world, std::uint64_t seed) : world_(world) {
  const mjModel* model = world_.model();
  mjData* data = world_.data();
  const auto& rig = world_.rig();
  servos_.reserve(rig.joints.size());
  for (std::size_t i = 0; i < rig.joints.size(); ++i) {
    servos_.emplace_back(ServoParams::from_joint(rig.joints[i], world_.timestep_s()),
                         mix_seed(seed, i), rig.joints[i].initial_position_rad);
  }
  // Gains from each joint's inertia at the initial pose (diagonal of the mass matrix, rotor
  // armature included): a critically damped second-order loop at kDriveBandwidthHz.
  mj_forward(model, data);
  const double omega = 2 * std::numbers::pi * kDriveBandwidthHz;
  for (const auto& joint : world_.joints()) {
    const double inertia = data->qM[model->dof_Madr[joint.dof_address]];
    gains_.push_back({inertia * omega * omega, 2.0 * kDriveDampingRatio * inertia * omega});
  }
  WorldSnapshot prototype;
  prototype.resize_for(model);
  render_snapshots_ = std::make_unique<hal::TripleBuffer<WorldSnapshot>>(prototype);
  truth_snapshots_ = std::make_unique<hal::TripleBuffer<WorldSnapshot>>(prototype);
}

GroupLink& PhysicsLoop::add_group(const std::string& group_name, const std::vector<int>& joints) {
  auto link = std::make_unique<GroupLink>();
  link->name = group_name;
  link->joints = joints;
  groups_.push_back(std::move(link));
  return *groups_.back();
}

TouchLink& PhysicsLoop::add_touch_sensor(const std::string& sensor_name,
                                         const std::vector<int>& bodies) {
  auto link = std::make_unique<TouchLink>();
  link->name = sensor_name;
  link->end_effector_body.assign(static_cast<std::size_t>(world_.model()->nbody), 0);
  for (const int body : bodies) link->end_effector_body[static_cast<std::size_t>(body)] = 1;
  touches_.push_back(std::move(link));
  return *touches_.back();
}

void PhysicsLoop::activate() {
  set_kinematic_joints();
  mj_forward(world_.model(), world_.data());
  for (std::size_t i = 0; i < servos_.size(); ++i) {
    servos_[i].observe(world_.data()->qpos[world_.joints()[i].qpos_address]);
  }
  publish(0);
}

void PhysicsLoop::set_kinematic_joints() noexcept {
  mjData* data = world_.data();
  const auto& joints = world_.joints();
  for (std::size_t i = 0; i < joints.size(); ++i) {
    if (!joints[i].kinematic) continue;
    data->qpos[joints[i].qpos_address] = servos_[i].output_position_rad();
    data->qvel[joints[i].dof_address] = servos_[i].output_velocity_rad_s();
  }
}

hal::Status PhysicsLoop::update(const hal::LoopTick& tick) noexcept {
  return step_once(tick.now_ns);
}

hal::Status PhysicsLoop::step_once(std::int64_t stamp_ns) noexcept {
  if (faulted_.load(std::memory_order_relaxed)) return hal::Status::kFault;
  const mjModel* model = world_.model();
  mjData* data = world_.data();
  const auto& joints = world_.joints();
  try {
    // Newest commands of every group.
    for (auto& group : groups_) {
      if (group->commands.version() == group->commands_seen) continue;
      GroupCommands block;
      if (!group->commands.try_read(block, &group->commands_seen)) continue;
      const std::size_t count = std::min<std::size_t>(block.count, group->joints.size());
      for (std::size_t k = 0; k < count; ++k) {
        (void)servos_[static_cast<std::size_t>(group->joints[k])].command(block.commands[k]);
      }
    }
    // Servos, then the drives of the physics joints: PD on the servo reference plus the
    // gravity and Coriolis torque of the last step as feed-forward, saturated at the effort
    // limit by the actuator's control range.
    for (std::size_t i = 0; i < joints.size(); ++i) {
      servos_[i].step();
      const auto& joint = joints[i];
      if (joint.kinematic) continue;
      const double q = data->qpos[joint.qpos_address];
      const double qdot = data->qvel[joint.dof_address];
      const double torque = gains_[i].kp_nm_rad * (servos_[i].output_position_rad() - q) +
                            gains_[i].kd_nm_s_rad * (servos_[i].output_velocity_rad_s() - qdot) +
                            data->qfrc_bias[joint.dof_address];
      data->ctrl[joint.actuator_id] = torque;
    }
    // Scripted objects follow their paths (time of the state being computed).
    const double t_next = data->time + model->opt.timestep;
    for (const auto& object : world_.objects()) {
      if (object.mocap_id < 0) continue;
      const auto p = scripted_position(*object.config, t_next);
      std::copy(p.begin(), p.end(), data->mocap_pos + 3 * object.mocap_id);
    }
    mj_step(model, data);
    // Kinematic joints are exactly where their servo put them (the integrator does not move
    // them).
    set_kinematic_joints();
    if (data->warning[mjWARN_BADQACC].number > 0) {
      faulted_.store(true, std::memory_order_relaxed);
      return hal::Status::kFault;
    }
    for (std::size_t i = 0; i < joints.size(); ++i) {
      servos_[i].observe(data->qpos[joints[i].qpos_address]);
    }
    steps_.fetch_add(1, std::memory_order_relaxed);
    publish(stamp_ns);
    return hal::Status::kOk;
  } catch (...) {
    faulted_.store(true, std::memory_order_relaxed);
    return hal::Status::kFault;
  }
}

void PhysicsLoop::publish(std::int64_t stamp_ns) noexcept {
  const mjModel* model = world_.model();
  const mjData* data = world_.data();
  const auto& joints = world_.joints();
  const auto& rig = world_.rig();

  for (auto& group : groups_) {
    GroupReadings readings;
    readings.stamp_ns = stamp_ns;
    readings.count = static_cast<std::uint32_t>(group->joints.size());
    for (std::size_t k = 0; k < group->joints.size(); ++k) {
      const auto i = static_cast<std::size_t>(group->joints[k]);
      auto& state = readings.states[k];
      state.position_rad = servos_[i].encoder_position_rad();
      state.velocity_rad_s = servos_[i].encoder_velocity_rad_s();
      state.effort_nm = joints[i].kinematic ? 0.0 : data->actuator_force[joints[i].actuator_id];
      const double q = data->qpos[joints[i].qpos_address];
      // Within 1 mrad: a servo resting at a limit sits off it by its motion error (a few 0.1
      // mrad), an arm by its stop's compliance.
      const double at_limit_tolerance = 1e-3;
      if (q <= rig.joints[i].min_position_rad + at_limit_tolerance ||
          q >= rig.joints[i].max_position_rad - at_limit_tolerance) {
        state.status_bits |= hal::kJointAtLimit;
      }
    }
    group->readings.write(readings);
  }

  for (auto& touch : touches_) {
    hal::TouchReading reading;
    reading.stamp_ns = stamp_ns;
    double strongest = -1.0;
    for (int c = 0; c < data->ncon; ++c) {
      const mjContact& contact = data->contact[c];
      const int body1 = model->geom_bodyid[contact.geom1];
      const int body2 = model->geom_bodyid[contact.geom2];
      const bool on1 = touch->end_effector_body[static_cast<std::size_t>(body1)] != 0;
      const bool on2 = touch->end_effector_body[static_cast<std::size_t>(body2)] != 0;
      if (on1 == on2) continue;          // Not the end effector, or the hand touching itself.
      if (contact.dist > 0.0) continue;  // Within the margin but not touching.
      mjtNum force[6];
      mj_contactForce(model, data, c, force);
      reading.in_contact = true;
      reading.normal_force_n += std::abs(force[0]);
      if (std::abs(force[0]) > strongest) {
        strongest = std::abs(force[0]);
        const int other_geom = on1 ? contact.geom2 : contact.geom1;
        const int other_body = on1 ? body2 : body1;
        // Scene objects are named bodies; the floor is a named geom of the world body.
        const char* name = other_body > 0 ? model->names + model->name_bodyadr[other_body]
                                          : model->names + model->name_geomadr[other_geom];
        std::strncpy(reading.object_name.data(), name, reading.object_name.size() - 1);
        reading.object_name.back() = '\0';
      }
    }
    touch->reading.write(reading);
  }

  const std::uint64_t steps = steps_.load(std::memory_order_relaxed);
  render_snapshots_->back().capture(model, data, stamp_ns, steps);
  render_snapshots_->publish();
  truth_snapshots_->back().capture(model, data, stamp_ns, steps);
  truth_snapshots_->publish();
}

}  // namespace cambio::sim
