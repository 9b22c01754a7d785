#include "cambio/sim/physics_loop.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <stdexcept>

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

PhysicsLoop::PhysicsLoop(World& world, hal::Clock& clock, std::uint64_t seed)
    : world_(world), clock_(clock), drives_(world.joints().size()), events_(world.joints().size()) {
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
  const double omega = 2.0 * std::numbers::pi * kDriveBandwidthHz;
  for (const auto& joint : world_.joints()) {
    const double inertia = data->qM[model->dof_Madr[joint.dof_address]];
    gains_.push_back({inertia * omega * omega, 2.0 * kDriveDampingRatio * inertia * omega});
  }
  WorldSnapshot prototype;
  prototype.resize_for(model);
  render_snapshots_ = std::make_unique<hal::TripleBuffer<WorldSnapshot>>(prototype);
  truth_snapshots_ = std::make_unique<hal::TripleBuffer<WorldSnapshot>>(prototype);
}

void PhysicsLoop::require_inactive(const char* what) const {
  if (active_) {
    throw std::logic_error(std::string("sim: ") + what +
                           " must be set up before the physics loop is activated");
  }
}

GroupLink& PhysicsLoop::add_group(const std::string& group_name, const std::vector<int>& joints) {
  require_inactive("a joint group");
  if (joints.size() > kMaxJointsPerGroup) {
    throw std::invalid_argument("sim: joint group '" + group_name + "' has more than " +
                                std::to_string(kMaxJointsPerGroup) + " joints");
  }
  auto link = std::make_unique<GroupLink>();
  link->name = group_name;
  link->joints = joints;
  groups_.push_back(std::move(link));
  // Readings exist as soon as the group does (drives not ready yet).
  publish_group(*groups_.back(), clock_.now_ns());
  return *groups_.back();
}

void PhysicsLoop::add_follower(const std::string& group_name, const std::vector<int>& joints,
                               const hal::JointStateSource& leader) {
  require_inactive("a followed joint group");
  auto link = std::make_unique<FollowLink>();
  link->name = group_name;
  link->joints = joints;
  link->leader = &leader;
  link->latest.resize(joints.size());
  const mjData* data = world_.data();
  for (const int index : joints) {
    Drive& drive = drives_[static_cast<std::size_t>(index)];
    drive.followed = true;
    // Until the leader reports, the joint stays where it is.
    drive.follow_position_rad =
        data->qpos[world_.joints()[static_cast<std::size_t>(index)].qpos_address];
    drive.follow_velocity_rad_s = 0.0;
  }
  followers_.push_back(std::move(link));
}

TouchLink& PhysicsLoop::add_touch_sensor(const std::string& sensor_name,
                                         const std::vector<int>& bodies) {
  require_inactive("a touch sensor");
  auto link = std::make_unique<TouchLink>();
  link->name = sensor_name;
  link->end_effector_body.assign(static_cast<std::size_t>(world_.model()->nbody), 0);
  for (const int body : bodies) link->end_effector_body[static_cast<std::size_t>(body)] = 1;
  touches_.push_back(std::move(link));
  return *touches_.back();
}

void PhysicsLoop::inject_fault(int joint, std::uint16_t emcy_error_code) noexcept {
  if (joint < 0 || static_cast<std::size_t>(joint) >= events_.size()) return;
  events_[static_cast<std::size_t>(joint)].fault.store(kFaultPending | emcy_error_code,
                                                       std::memory_order_release);
}

void PhysicsLoop::inject_comm_loss(int joint) noexcept {
  if (joint < 0 || static_cast<std::size_t>(joint) >= events_.size()) return;
  events_[static_cast<std::size_t>(joint)].comm_loss.store(true, std::memory_order_release);
}

void PhysicsLoop::freeze_feedback(int joint, bool frozen) noexcept {
  if (joint < 0 || static_cast<std::size_t>(joint) >= events_.size()) return;
  events_[static_cast<std::size_t>(joint)].freeze.store(frozen, std::memory_order_release);
}

void PhysicsLoop::activate() {
  // Transitions 0 and 1: the drives boot and wait, disabled, for an enable request.
  for (std::size_t i = 0; i < drives_.size(); ++i) {
    if (drives_[i].state == hal::DriveState::kNotReadyToSwitchOn) {
      enter(i, hal::DriveState::kSwitchOnDisabled);
    }
  }
  set_kinematic_joints();
  mj_forward(world_.model(), world_.data());
  for (std::size_t i = 0; i < servos_.size(); ++i) {
    servos_[i].observe(world_.data()->qpos[world_.joints()[i].qpos_address]);
  }
  publish(clock_.now_ns());
  active_ = true;
}

void PhysicsLoop::deactivate() noexcept {
  if (!active_) return;
  for (std::size_t i = 0; i < drives_.size(); ++i) {
    Drive& drive = drives_[i];
    drive.goal = hal::DriveRequest::kDisable;
    if (drive.state == hal::DriveState::kFaultReactionActive) {
      enter(i, hal::DriveState::kFault);  // A fault stays latched until a reset.
    } else if (drive.state != hal::DriveState::kFault) {
      enter(i, hal::DriveState::kSwitchOnDisabled);
    }
  }
  // Requests and commands written before now are not carried into a later activation.
  for (auto& group : groups_) {
    for (std::size_t k = 0; k < group->joints.size(); ++k) {
      group->requests_seen[k] = group->requests[k].load(std::memory_order_acquire);
    }
    group->commands_seen = group->commands.version();
  }
  publish(clock_.now_ns());
  active_ = false;
}

void PhysicsLoop::enter(std::size_t joint, hal::DriveState state) noexcept {
  drives_[joint].state = state;
  ServoModel& servo = servos_[joint];
  const double measured_rad = world_.data()->qpos[world_.joints()[joint].qpos_address];
  // Enabled, or stopped: hold where the joint is (an arm pressed against something stops
  // pushing). Still moving: brake on the acceleration limit first, then hold where it stopped.
  if (state == hal::DriveState::kOperationEnabled || servo.at_rest()) {
    servo.hold_at(measured_rad);
  } else {
    servo.brake_to_stop();
  }
}

void PhysicsLoop::raise_fault(std::size_t joint, std::uint16_t error_code) noexcept {
  Drive& drive = drives_[joint];
  drive.error_code = error_code;
  // The fault latches: a request made before it (an enable, a reset) does not undo it.
  drive.goal = hal::DriveRequest::kDisable;
  if (!hal::is_faulted(drive.state)) enter(joint, hal::DriveState::kFaultReactionActive);
}

void PhysicsLoop::advance_drive(std::size_t joint) noexcept {
  Drive& drive = drives_[joint];
  DriveEvents& events = events_[joint];
  // One transition per step, from the state the last reading showed.
  if (drive.state == hal::DriveState::kFaultReactionActive) {
    if (servos_[joint].at_rest()) enter(joint, hal::DriveState::kFault);  // Transition 14.
  } else {
    const hal::DriveState next = hal::next_drive_state(drive.state, drive.goal);
    if (next != drive.state) {
      if (drive.state == hal::DriveState::kFault) {
        // Transition 15 (fault reset): the error and a lost link are cleared.
        drive.error_code = 0;
        drive.comm_lost = false;
      }
      enter(joint, next);
    }
  }
  // Injected events after the transition, so a fault reaction shows for at least one step.
  if (events.comm_loss.exchange(false, std::memory_order_acq_rel) && !drive.comm_lost) {
    // A drive that loses its master runs its fault reaction (CiA 402 abort connection option
    // "fault"); the master, no longer hearing it, keeps its last reading.
    drive.comm_lost = true;
    raise_fault(joint, kCommLossErrorCode);
  }
  const std::uint32_t fault = events.fault.exchange(0, std::memory_order_acq_rel);
  if (fault != 0) raise_fault(joint, static_cast<std::uint16_t>(fault & 0xFFFFu));
  drive.feedback_frozen = events.freeze.load(std::memory_order_acquire);
}

void PhysicsLoop::take_requests() noexcept {
  for (auto& group : groups_) {
    for (std::size_t k = 0; k < group->joints.size(); ++k) {
      const std::uint32_t word = group->requests[k].load(std::memory_order_acquire);
      if (word == group->requests_seen[k]) continue;
      group->requests_seen[k] = word;
      drives_[static_cast<std::size_t>(group->joints[k])].goal =
          static_cast<hal::DriveRequest>(word & 0xFFu);
    }
  }
}

void PhysicsLoop::take_commands() noexcept {
  for (auto& group : groups_) {
    if (group->commands.version() == group->commands_seen) continue;
    GroupCommands block;
    if (!group->commands.try_read(block, &group->commands_seen)) continue;
    const std::size_t count = std::min<std::size_t>(block.count, group->joints.size());
    for (std::size_t k = 0; k < count; ++k) {
      const auto i = static_cast<std::size_t>(group->joints[k]);
      // Taken before this step's transitions: a target written while the drive was not yet
      // enabled is dropped, never executed once it is.
      if (!hal::is_enabled(drives_[i].state)) continue;
      (void)servos_[i].command(block.commands[k]);
    }
  }
}

void PhysicsLoop::take_leaders() noexcept {
  const auto& rig = world_.rig();
  for (auto& follower : followers_) {
    // On a torn or missing read the joints keep the leader's last good positions.
    if (!follower->leader->latest(follower->latest)) continue;
    for (std::size_t k = 0; k < follower->joints.size(); ++k) {
      const auto i = static_cast<std::size_t>(follower->joints[k]);
      const hal::JointState& state = follower->latest[k];
      if (!std::isfinite(state.position_rad)) continue;
      Drive& drive = drives_[i];
      drive.follow_position_rad = std::clamp(state.position_rad, rig.joints[i].min_position_rad,
                                             rig.joints[i].max_position_rad);
      drive.follow_velocity_rad_s =
          std::isfinite(state.velocity_rad_s) ? state.velocity_rad_s : 0.0;
    }
  }
}

double PhysicsLoop::reference_position_rad(std::size_t joint) const noexcept {
  const Drive& drive = drives_[joint];
  return drive.followed ? drive.follow_position_rad : servos_[joint].output_position_rad();
}

double PhysicsLoop::reference_velocity_rad_s(std::size_t joint) const noexcept {
  const Drive& drive = drives_[joint];
  return drive.followed ? drive.follow_velocity_rad_s : servos_[joint].output_velocity_rad_s();
}

void PhysicsLoop::set_kinematic_joints() noexcept {
  mjData* data = world_.data();
  const auto& joints = world_.joints();
  for (std::size_t i = 0; i < joints.size(); ++i) {
    if (!joints[i].kinematic) continue;
    data->qpos[joints[i].qpos_address] = reference_position_rad(i);
    data->qvel[joints[i].dof_address] = reference_velocity_rad_s(i);
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
    take_requests();
    take_commands();
    take_leaders();
    for (std::size_t i = 0; i < drives_.size(); ++i) advance_drive(i);
    // Servos, then the drives of the physics joints: PD on the reference (the servo's, or the
    // leader's for a followed joint) plus the gravity and Coriolis torque of the last step and
    // the command's effort feed-forward, saturated at the effort limit by the actuator's
    // control range.
    for (std::size_t i = 0; i < joints.size(); ++i) {
      const bool followed = drives_[i].followed;
      if (!followed) servos_[i].step();
      const auto& joint = joints[i];
      if (joint.kinematic) continue;
      const double q = data->qpos[joint.qpos_address];
      const double qdot = data->qvel[joint.dof_address];
      const double feedforward_nm = followed ? 0.0 : servos_[i].effort_feedforward_nm();
      data->ctrl[joint.actuator_id] = gains_[i].kp_nm_rad * (reference_position_rad(i) - q) +
                                      gains_[i].kd_nm_s_rad * (reference_velocity_rad_s(i) - qdot) +
                                      data->qfrc_bias[joint.dof_address] + feedforward_nm;
    }
    // Scripted objects follow their paths (time of the state being computed).
    const double t_next = data->time + model->opt.timestep;
    for (const auto& object : world_.objects()) {
      if (object.mocap_id < 0) continue;
      const auto p = scripted_position(*object.config, t_next);
      std::copy(p.begin(), p.end(), data->mocap_pos + 3 * object.mocap_id);
    }
    mj_step(model, data);
    // Kinematic joints are exactly where their servo (or leader) put them: the integrator does
    // not move them.
    set_kinematic_joints();
    if (data->warning[mjWARN_BADQACC].number > 0) {
      faulted_.store(true, std::memory_order_relaxed);
      return report_fault("physics: MuJoCo's accelerations diverged (bad qacc)");
    }
    for (std::size_t i = 0; i < joints.size(); ++i) {
      servos_[i].observe(data->qpos[joints[i].qpos_address]);
    }
    steps_.fetch_add(1, std::memory_order_relaxed);
    publish(stamp_ns);
    return hal::Status::kOk;
  } catch (const std::exception& error) {
    faulted_.store(true, std::memory_order_relaxed);
    return report_fault(error.what());
  } catch (...) {
    faulted_.store(true, std::memory_order_relaxed);
    return report_fault("physics: unknown exception");
  }
}

void PhysicsLoop::publish_group(GroupLink& group, std::int64_t stamp_ns) noexcept {
  const mjData* data = world_.data();
  const auto& joints = world_.joints();
  const auto& rig = world_.rig();
  GroupReadings readings;
  readings.count = static_cast<std::uint32_t>(group.joints.size());
  readings.stamp_ns = std::numeric_limits<std::int64_t>::min();
  for (std::size_t k = 0; k < group.joints.size(); ++k) {
    const auto i = static_cast<std::size_t>(group.joints[k]);
    Drive& drive = drives_[i];
    // A lost or frozen joint keeps its last reading, stamp included: what a master sees when a
    // node's feedback frames stop.
    if (!drive.comm_lost && !drive.feedback_frozen) {
      hal::JointState& state = drive.reading;
      state.position_rad = servos_[i].encoder_position_rad();
      state.velocity_rad_s = servos_[i].encoder_velocity_rad_s();
      state.effort_nm = joints[i].kinematic ? 0.0 : data->actuator_force[joints[i].actuator_id];
      state.stamp_ns = stamp_ns;
      state.error_code = drive.error_code;
      state.drive_state = drive.state;
      state.status_bits = hal::kJointOk;
      const double q = data->qpos[joints[i].qpos_address];
      // Within 1 mrad: a servo resting at a limit sits off it by its motion error (a few 0.1
      // mrad), an arm by its stop's compliance.
      const double at_limit_tolerance = 1e-3;
      if (q <= rig.joints[i].min_position_rad + at_limit_tolerance ||
          q >= rig.joints[i].max_position_rad - at_limit_tolerance) {
        state.status_bits |= hal::kJointAtLimit;
      }
      if (!hal::is_enabled(drive.state)) state.status_bits |= hal::kJointNotEnabled;
      if (hal::is_faulted(drive.state)) state.status_bits |= hal::kJointFault;
    }
    hal::JointState& out = readings.states[k];
    out = drive.reading;
    if (drive.comm_lost) out.status_bits |= hal::kJointCommLost;
    readings.stamp_ns = std::max(readings.stamp_ns, out.stamp_ns);
  }
  if (group.joints.empty()) readings.stamp_ns = stamp_ns;
  group.readings.write(readings);
}

void PhysicsLoop::publish(std::int64_t stamp_ns) noexcept {
  const mjModel* model = world_.model();
  const mjData* data = world_.data();

  for (auto& group : groups_) publish_group(*group, stamp_ns);

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
