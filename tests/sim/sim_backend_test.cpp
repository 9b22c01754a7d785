// The sim behind the HAL under the lockstep executor: determinism, limits, touch, ground truth.
#include "cambio/sim/sim_backend.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "cambio/hal/manual_clock.hpp"
#include "cambio/runtime/realtime_executor.hpp"
#include "lockstep_sim.hpp"
#include "sim_test_support.hpp"

namespace cambio::sim {
namespace {

std::uint64_t fnv1a(std::span<const std::uint8_t> bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (const std::uint8_t b : bytes) hash = (hash ^ b) * 0x100000001b3ULL;
  return hash;
}

/// Enables its groups' drives, then commands every joint along sines and records what the
/// encoders report.
class ExerciseLoop final : public hal::Loop {
 public:
  ExerciseLoop(std::vector<std::unique_ptr<hal::JointGroup>> groups, std::size_t cycles)
      : groups_(std::move(groups)) {
    for (auto& group : groups_) {
      commands_.emplace_back(group->info().joints.size());
      states_.emplace_back(group->info().joints.size());
    }
    trajectory_.reserve(cycles * 16);
  }
  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    const double t = static_cast<double>(tick.deadline_ns) * 1e-9;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      if (tick.cycle == 0 && groups_[g]->request(hal::DriveRequest::kEnable) != hal::Status::kOk) {
        return hal::Status::kFault;
      }
      std::int64_t stamp = 0;
      if (groups_[g]->read(states_[g], stamp) != hal::Status::kOk) return hal::Status::kFault;
      for (const auto& state : states_[g]) {
        if (trajectory_.size() < trajectory_.capacity()) trajectory_.push_back(state.position_rad);
      }
      const auto& info = groups_[g]->info();
      for (std::size_t k = 0; k < commands_[g].size(); ++k) {
        const auto& limits = info.limits[k];
        const double middle = 0.5 * (limits.min_position_rad + limits.max_position_rad);
        const double half = 0.25 * (limits.max_position_rad - limits.min_position_rad);
        commands_[g][k].value = middle + half * std::sin(3.0 * t + static_cast<double>(k));
      }
      if (groups_[g]->write(commands_[g]) != hal::Status::kOk) return hal::Status::kFault;
    }
    return hal::Status::kOk;
  }
  const std::vector<double>& trajectory() const { return trajectory_; }

 private:
  std::string name_ = "joint";
  std::vector<std::unique_ptr<hal::JointGroup>> groups_;
  std::vector<std::vector<hal::JointCommand>> commands_;
  std::vector<std::vector<hal::JointState>> states_;
  std::vector<double> trajectory_;
};

/// Grabs both eyes each cycle and hashes the frames.
class StereoLoop final : public hal::Loop {
 public:
  StereoLoop(std::unique_ptr<hal::Camera> left, std::unique_ptr<hal::Camera> right,
             std::size_t cycles)
      : left_(std::move(left)), right_(std::move(right)) {
    const auto& k = left_->info().intrinsics;
    left_image_.resize(k.width_px, k.height_px, left_->info().format);
    right_image_.resize(k.width_px, k.height_px, right_->info().format);
    hashes_.reserve(2 * cycles);
  }
  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick&) noexcept override {
    if (left_->grab(left_image_) != hal::Status::kOk) return hal::Status::kFault;
    if (right_->grab(right_image_) != hal::Status::kOk) return hal::Status::kFault;
    if (left_image_.stamp_ns != right_image_.stamp_ns) return hal::Status::kFault;
    if (hashes_.size() + 2 <= hashes_.capacity()) {
      hashes_.push_back(fnv1a(left_image_.bytes()));
      hashes_.push_back(fnv1a(right_image_.bytes()));
    }
    return hal::Status::kOk;
  }
  const std::vector<std::uint64_t>& hashes() const { return hashes_; }

 private:
  std::string name_ = "camera";
  std::unique_ptr<hal::Camera> left_, right_;
  hal::Image left_image_, right_image_;
  std::vector<std::uint64_t> hashes_;
};

struct RunResult {
  std::vector<double> trajectory;
  std::vector<std::uint64_t> hashes;
  std::uint64_t physics_allocations = 0;
  bool cameras_declare_allocations = false;
  std::uint64_t failed_updates = 0;
};

RunResult run_lockstep(std::uint64_t seed, double image_noise_std, double seconds) {
  auto rig = testing::load_shipped_rig();
  testing::use_small_cameras(rig);
  for (auto& camera : rig.cameras) camera.image_noise_std = image_noise_std;
  testing::LockstepSim sim(rig, testing::load_shipped_scene("distractors"), seed);
  const auto cycles = static_cast<std::size_t>(seconds * 1000) + 1;
  std::vector<std::unique_ptr<hal::JointGroup>> groups;
  groups.push_back(sim.backend->make_joint_group("head"));
  groups.push_back(sim.backend->make_joint_group("left_arm"));
  ExerciseLoop joint_loop(std::move(groups), cycles);
  std::unique_ptr<hal::Camera> left = sim.backend->make_camera("left_eye");
  std::unique_ptr<hal::Camera> right = sim.backend->make_camera("right_eye");
  const bool cameras_declare_allocations = left->grab_allocates() && right->grab_allocates();
  StereoLoop camera_loop(std::move(left), std::move(right),
                         static_cast<std::size_t>(seconds * 30) + 2);
  sim.add_loop(joint_loop, 1000.0);
  sim.add_loop(camera_loop, 30.0);
  sim.start();
  sim.run_for_s(seconds);
  sim.stop();
  RunResult result{joint_loop.trajectory(), camera_loop.hashes()};
  result.cameras_declare_allocations = cameras_declare_allocations;
  for (const auto& stats : sim.executor.statistics()) {
    if (stats.name == "physics") result.physics_allocations = stats.allocations;
    result.failed_updates += stats.failed_updates;
  }
  return result;
}

TEST(SimDeterminismTest, SameSeedGivesTheSameJointTrajectoryAndImages) {
  const RunResult a = run_lockstep(11, 2.0, 1.0);
  const RunResult b = run_lockstep(11, 2.0, 1.0);
  EXPECT_EQ(a.failed_updates, 0u);
  ASSERT_GT(a.trajectory.size(), 9'000u);
  ASSERT_GE(a.hashes.size(), 60u);
  EXPECT_EQ(a.trajectory, b.trajectory);
  EXPECT_EQ(a.hashes, b.hashes);
  // Scripted objects move and the head turns: frames change over the run.
  EXPECT_NE(a.hashes.front(), a.hashes[a.hashes.size() - 2]);
  // The physics step allocates nothing after configure; rendering does, in Mesa, and the cameras
  // say so.
  EXPECT_EQ(a.physics_allocations, 0u);
  EXPECT_TRUE(a.cameras_declare_allocations);
}

TEST(SimRealtimeTest, RunsUnderTheRealtimeExecutorWithCamerasOnTheirOwnThread) {
  auto rig = testing::load_shipped_rig();
  testing::use_small_cameras(rig);
  runtime::RealtimeExecutor executor;
  auto backend =
      testing::make_sim(rig, testing::load_shipped_scene("vergence"), executor.clock(), 0, true);
  std::vector<std::unique_ptr<hal::JointGroup>> groups;
  groups.push_back(backend->make_joint_group("head"));
  ExerciseLoop joint_loop(std::move(groups), 1000);
  StereoLoop camera_loop(backend->make_camera("left_eye"), backend->make_camera("right_eye"), 100);
  const auto physics = backend->loops().front();
  executor.add_loop({physics.loop, runtime::LoopSchedule{physics.rate_hz, 0, -1, {}}});
  executor.add_loop({&joint_loop, runtime::LoopSchedule{1000.0, 0, -1, {}}});
  executor.add_loop({&camera_loop, runtime::LoopSchedule{20.0, 0, -1, {}}});
  backend->configure();
  backend->activate();
  std::atomic<bool> stop{false};
  (void)executor.run(stop, 500'000'000, {});
  backend->deactivate();
  for (const auto& stats : executor.statistics()) {
    EXPECT_EQ(stats.failed_updates, 0u) << stats.name;
    EXPECT_GT(stats.cycles, 0u) << stats.name;
  }
  EXPECT_GT(camera_loop.hashes().size(), 2u) << "both eyes grabbed on the camera thread";
  // Ground truth renders from this thread after the camera thread used the GL context.
  hal::Image rgb;
  EXPECT_NO_THROW(backend->ground_truth().render("left_eye", 0, 0, ViewOptions{}, rgb, nullptr));
}

TEST(SimDeterminismTest, DifferentSeedGivesDifferentNoise) {
  const RunResult a = run_lockstep(11, 2.0, 0.3);
  const RunResult b = run_lockstep(12, 2.0, 0.3);
  ASSERT_EQ(a.trajectory.size(), b.trajectory.size());
  EXPECT_NE(a.trajectory, b.trajectory) << "servo motion noise must follow the seed";
  ASSERT_EQ(a.hashes.size(), b.hashes.size());
  for (std::size_t i = 0; i < a.hashes.size(); ++i) {
    EXPECT_NE(a.hashes[i], b.hashes[i]) << "image noise must follow the seed (frame " << i << ")";
  }
}

/// Requests kEnable for the whole group and steps until every drive is operation enabled.
void enable(hal::JointGroup& group, PhysicsLoop& physics, std::int64_t& t_ns) {
  ASSERT_EQ(group.request(hal::DriveRequest::kEnable), hal::Status::kOk);
  std::vector<hal::JointState> states(group.info().joints.size());
  for (int step = 0; step < 10; ++step) {
    ASSERT_EQ(physics.step_once(t_ns += 1'000'000), hal::Status::kOk);
    std::int64_t stamp = 0;
    ASSERT_EQ(group.read(states, stamp), hal::Status::kOk);
    if (std::all_of(states.begin(), states.end(), [](const hal::JointState& state) {
          return state.drive_state == hal::DriveState::kOperationEnabled;
        })) {
      return;
    }
  }
  FAIL() << group.info().name << " did not reach operation enabled";
}

TEST(SimJointGroupTest, CommandsBeyondLimitsAreClampedFlaggedAndNeverExecuted) {
  auto rig = testing::load_shipped_rig();
  hal::ManualClock clock;
  auto sim = testing::make_sim(rig, testing::load_shipped_scene("table"), clock);
  auto& backend = *sim;
  auto head = backend.make_joint_group("head");
  auto arm = backend.make_joint_group("right_arm");
  auto& physics = backend.physics();
  backend.activate();
  std::int64_t t_ns = 0;
  enable(*head, physics, t_ns);
  enable(*arm, physics, t_ns);
  std::vector<hal::JointCommand> head_commands(head->info().joints.size());
  std::vector<hal::JointCommand> arm_commands(arm->info().joints.size());
  std::vector<hal::JointState> states(head->info().joints.size());
  for (std::size_t k = 0; k < head_commands.size(); ++k) {
    head_commands[k].value = head->info().limits[k].max_position_rad + 1.0;
  }
  for (std::size_t k = 0; k < arm_commands.size(); ++k) {
    arm_commands[k].value = arm->info().limits[k].min_position_rad - 1.0;
  }
  ASSERT_EQ(head->write(head_commands), hal::Status::kOk);
  ASSERT_EQ(arm->write(arm_commands), hal::Status::kOk);
  auto& truth = backend.ground_truth();
  for (int step = 0; step < 4'000; ++step) {
    ASSERT_EQ(physics.step_once(t_ns += 1'000'000), hal::Status::kOk);
    if (step % 20 != 0) continue;
    for (const auto* group : {head.get(), arm.get()}) {
      for (std::size_t k = 0; k < group->info().joints.size(); ++k) {
        const auto& limits = group->info().limits[k];
        const double q = truth.joint_position_rad(group->info().joints[k]);
        // Kinematic head joints are exact. Arm joints are driven through physics: their servo
        // reference stops at the limit, and the joint stop (MuJoCo's soft limit constraint,
        // time constant 4 ms) yields to the shoulder's coupling torque by well under 1 mrad
        // while the arm swings.
        const double tolerance = group == head.get() ? 0.0 : 1e-3;
        ASSERT_GE(q, limits.min_position_rad - tolerance)
            << group->info().joints[k] << " step " << step;
        ASSERT_LE(q, limits.max_position_rad + tolerance) << group->info().joints[k];
      }
    }
  }
  std::int64_t stamp = 0;
  ASSERT_EQ(head->read(states, stamp), hal::Status::kOk);
  for (std::size_t k = 0; k < states.size(); ++k) {
    EXPECT_TRUE(states[k].status_bits & hal::kJointCommandClamped) << head->info().joints[k];
    EXPECT_TRUE(states[k].status_bits & hal::kJointAtLimit) << head->info().joints[k];
    EXPECT_NEAR(states[k].position_rad, head->info().limits[k].max_position_rad, 1e-3);
  }
  // A command inside the limits clears the clamp flag.
  for (std::size_t k = 0; k < head_commands.size(); ++k) head_commands[k].value = 0.0;
  ASSERT_EQ(head->write(head_commands), hal::Status::kOk);
  ASSERT_EQ(head->read(states, stamp), hal::Status::kOk);
  for (const auto& state : states) EXPECT_FALSE(state.status_bits & hal::kJointCommandClamped);
  // Wrong sizes are rejected.
  EXPECT_EQ(head->write(std::span<const hal::JointCommand>(head_commands.data(), 2)),
            hal::Status::kRejected);
}

TEST(SimJointGroupTest, ArmsTrackTheirServoThroughPhysicsAndEncodersQuantise) {
  auto rig = testing::load_shipped_rig();
  hal::ManualClock clock;
  auto sim = testing::make_sim(rig, testing::load_shipped_scene("vergence"), clock);
  auto& backend = *sim;
  auto arm = backend.make_joint_group("left_arm");
  auto& physics = backend.physics();
  backend.activate();
  std::int64_t t_ns = 0;
  enable(*arm, physics, t_ns);
  const std::vector<double> targets = {0.3, 0.4, 0.8, -0.3, 0.2};
  std::vector<hal::JointCommand> commands(targets.size());
  for (std::size_t k = 0; k < targets.size(); ++k) commands[k].value = targets[k];
  ASSERT_EQ(arm->write(commands), hal::Status::kOk);
  for (int step = 0; step < 3'000; ++step) {
    ASSERT_EQ(physics.step_once(t_ns += 1'000'000), hal::Status::kOk);
  }
  std::vector<hal::JointState> states(targets.size());
  std::int64_t stamp = 0;
  ASSERT_EQ(arm->read(states, stamp), hal::Status::kOk);
  const double count = 2 * std::numbers::pi / 65536.0;
  for (std::size_t k = 0; k < targets.size(); ++k) {
    const auto& name = arm->info().joints[k];
    const double truth = backend.ground_truth().joint_position_rad(name);
    EXPECT_NEAR(truth, targets[k], 0.01) << name << " settles at its target under gravity";
    EXPECT_NEAR(states[k].position_rad, truth, count / 2 + 1e-12) << name;
    EXPECT_NEAR(std::remainder(states[k].position_rad, count), 0.0, 1e-9) << name;
    EXPECT_NEAR(states[k].velocity_rad_s, 0.0, 0.05) << name;
  }
}

// A table and nothing else on it, so the hand meets the table first.
config::SceneConfig bare_table() {
  return config::load_scene_from_string(
      "objects:\n"
      "  - {name: table_top, shape: box, size_m: [0.6, 1.0, 0.04], xyz_m: [0.6, 0, 0.78]}\n",
      "bare_table.yaml");
}

TEST(SimTouchTest, FiresWhenTheHandIsDrivenIntoTheTableNotInFreeSpace) {
  auto rig = testing::load_shipped_rig();
  hal::ManualClock clock;
  auto sim = testing::make_sim(rig, bare_table(), clock);
  auto& backend = *sim;
  auto arm = backend.make_joint_group("left_arm");
  auto hand = backend.make_touch_sensor("left_hand");
  auto& physics = backend.physics();
  backend.configure();
  backend.activate();
  std::int64_t t = 0;
  enable(*arm, physics, t);
  std::vector<hal::JointCommand> commands(5);
  hal::TouchReading reading;
  auto settle = [&](int steps, bool expect_contact_free) {
    for (int k = 0; k < steps; ++k) {
      ASSERT_EQ(physics.step_once(t += 1'000'000), hal::Status::kOk);
      ASSERT_EQ(hand->read(reading), hal::Status::kOk);
      if (expect_contact_free) {
        ASSERT_FALSE(reading.in_contact) << "touch in free space at step " << k;
      }
    }
  };
  // Free space: the arm sweeps up and sideways above the table.
  commands[0].value = 0.5;   // shoulder yaw, outwards
  commands[1].value = -0.4;  // shoulder pitch, up
  ASSERT_EQ(arm->write(commands), hal::Status::kOk);
  settle(2'000, true);
  commands[0].value = 0.0;
  commands[1].value = -0.2;
  ASSERT_EQ(arm->write(commands), hal::Status::kOk);
  settle(2'000, true);
  EXPECT_EQ(reading.normal_force_n, 0.0);
  // Down into the table top (a straight arm meets it at about 0.42 rad).
  commands[1].value = 0.7;
  ASSERT_EQ(arm->write(commands), hal::Status::kOk);
  settle(2'500, false);
  EXPECT_TRUE(reading.in_contact);
  EXPECT_GT(reading.normal_force_n, 1.0);
  EXPECT_EQ(reading.object(), "table_top");
  EXPECT_EQ(reading.stamp_ns, t);
  // The table stopped the arm above where it was sent.
  EXPECT_LT(backend.ground_truth().joint_position_rad("left_shoulder_pitch"), 0.6);
}

TEST(SimGroundTruthTest, ScriptedObjectsFollowTheirPaths) {
  auto rig = testing::load_shipped_rig();
  hal::ManualClock clock;
  auto sim = testing::make_sim(rig, testing::load_shipped_scene("distractors"), clock);
  auto& backend = *sim;
  auto& physics = backend.physics();
  backend.activate();
  const Eigen::Vector3d start = backend.ground_truth().X_WO("crossing_ball").translation();
  EXPECT_NEAR(start.y(), 1.2, 1e-9);
  // Waypoints: starts moving at 1 s, crosses 2.4 m in 4 s; at 3 s it is halfway.
  for (int k = 0; k < 3'000; ++k) ASSERT_EQ(physics.step_once(k), hal::Status::kOk);
  const Eigen::Vector3d halfway = backend.ground_truth().X_WO("crossing_ball").translation();
  EXPECT_NEAR(halfway.y(), 0.0, 1e-6);
  EXPECT_NEAR(halfway.x(), 0.8, 1e-9);
}

TEST(SimBackendTest, RegistersAsTheSimBackendAndReportsItsPhysicsLoop) {
  const auto rig = testing::load_shipped_rig();
  hal::BackendFactory factory;
  // The application loads the experiment's scene and hands it to the maker.
  register_sim_backend(factory, rig, testing::load_shipped_scene("vergence"));
  ASSERT_TRUE(factory.has("sim"));
  hal::ManualClock clock;
  auto backend =
      factory.make("sim", config::hardware_description(rig), hal::BackendContext{&clock}, "test");
  const auto loops = backend->loops();
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].rate_hz, rig.sim.physics_rate_hz);
  EXPECT_EQ(loops[0].loop->name(), "physics");
  EXPECT_THROW(backend->make_joint_group("no_such_group"), std::runtime_error);
  EXPECT_THROW(backend->make_camera("no_such_camera"), std::runtime_error);
  auto head = backend->make_joint_group("head");
  EXPECT_THROW(backend->make_joint_group("head"), std::runtime_error) << "one writer per group";
  // Readings exist as soon as the group does; the drives boot on activate().
  std::vector<hal::JointState> states(head->info().joints.size());
  std::int64_t stamp = -1;
  ASSERT_EQ(head->read(states, stamp), hal::Status::kOk);
  EXPECT_EQ(states[0].drive_state, hal::DriveState::kNotReadyToSwitchOn);
  clock.advance_to_ns(7'000'000);
  backend->configure();
  backend->activate();
  ASSERT_EQ(head->read(states, stamp), hal::Status::kOk);
  EXPECT_EQ(stamp, 7'000'000) << "the first readings are stamped on the run's clock";
  for (const auto& state : states) {
    EXPECT_EQ(state.drive_state, hal::DriveState::kSwitchOnDisabled);
    EXPECT_EQ(state.stamp_ns, 7'000'000);
    EXPECT_TRUE(state.status_bits & hal::kJointNotEnabled);
  }
  EXPECT_THROW(backend->make_joint_group("left_arm"), std::logic_error)
      << "groups are made before the physics loop runs";
}

TEST(SimBackendTest, RefusesToBeBuiltWithoutTheRunsClock) {
  const auto rig = testing::load_shipped_rig();
  EXPECT_THROW(SimBackend(rig, testing::empty_scene(), config::hardware_description(rig),
                          hal::BackendContext{}),
               std::invalid_argument);
}

/// A sim whose head pans (so every step's view differs), stepped by hand to `steps`.
struct PanningHead {
  hal::ManualClock clock;
  std::unique_ptr<SimBackend> backend;
  std::unique_ptr<hal::JointGroup> head;
  std::unique_ptr<hal::Camera> left, right;
  std::int64_t t_ns = 0;

  explicit PanningHead(const config::RigConfig& rig)
      : backend(testing::make_sim(rig, testing::load_shipped_scene("vergence"), clock)),
        head(backend->make_joint_group("head")),
        left(backend->make_camera("left_eye")),
        right(backend->make_camera("right_eye")) {
    backend->activate();
    enable(*head, backend->physics(), t_ns);
    std::vector<hal::JointCommand> commands(head->info().joints.size());
    commands[0].value = 0.5;  // neck_pan
    EXPECT_EQ(head->write(commands), hal::Status::kOk);
  }
  void step_to(std::uint64_t steps) {
    while (backend->physics().steps() < steps) {
      ASSERT_EQ(backend->physics().step_once(t_ns += 1'000'000), hal::Status::kOk);
    }
  }
};

TEST(SimCameraTest, GrabNeverWaitsForTheRenderer) {
  auto rig = testing::load_shipped_rig();
  testing::use_small_cameras(rig);
  PanningHead sim(rig);
  sim.step_to(10);
  const auto& k = sim.left->info().intrinsics;
  hal::Image image(k.width_px, k.height_px, sim.left->info().format);
  // Another thread (ground truth for an evaluation, say) holds the renderer until the grab has
  // returned (or, if the grab waits for it, for 10 s; then the grab returns after the release).
  std::atomic<bool> held{false};
  std::atomic<bool> grab_returned{false};
  std::atomic<bool> released{false};
  std::thread holder([&] {
    const Renderer::Lease lease(sim.backend->renderer(), Renderer::Lease::Mode::kWait);
    held = true;
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!grab_returned && std::chrono::steady_clock::now() < give_up) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    released = true;
  });
  while (!held) std::this_thread::yield();
  const hal::Status busy = sim.left->grab(image);
  const bool returned_while_held = !released;
  grab_returned = true;
  holder.join();
  EXPECT_EQ(busy, hal::Status::kNoNewData) << "the camera loop skips a cycle, it does not wait";
  EXPECT_TRUE(returned_while_held) << "the grab waited for the renderer to be released";
  EXPECT_EQ(image.sequence, 0u) << "the image was left untouched";
  EXPECT_EQ(sim.left->grab(image), hal::Status::kOk) << "and grabs once the renderer is free";
}

TEST(SimCameraTest, BothEyesOfACycleSeeOneSnapshotWhateverRendersBetweenThem) {
  auto rig = testing::load_shipped_rig();
  testing::use_small_cameras(rig);
  testing::make_ideal(rig);
  PanningHead sim(rig);
  const auto& k = sim.left->info().intrinsics;
  hal::Image left_image(k.width_px, k.height_px, sim.left->info().format);
  hal::Image right_image(k.width_px, k.height_px, sim.right->info().format);
  sim.step_to(50);
  const std::int64_t stamp_50 = sim.t_ns;
  ASSERT_EQ(sim.left->grab(left_image), hal::Status::kOk);
  // Between the eyes' grabs: the head pans on, and ground truth renders the newer state.
  sim.step_to(250);
  hal::Image truth;
  sim.backend->ground_truth().render("right_eye", 0, 0, ViewOptions{}, truth, nullptr);
  EXPECT_EQ(truth.stamp_ns, sim.t_ns);
  ASSERT_EQ(sim.right->grab(right_image), hal::Status::kOk);
  EXPECT_EQ(left_image.stamp_ns, stamp_50);
  EXPECT_EQ(right_image.stamp_ns, stamp_50) << "a stereo pair has equal stamps";
  // What the right eye rendered is the instant of step 50, as a sim stopped there renders it.
  PanningHead reference(rig);
  reference.step_to(50);
  hal::Image expected(k.width_px, k.height_px, reference.right->info().format);
  ASSERT_EQ(reference.right->grab(expected), hal::Status::kOk);
  EXPECT_EQ(expected.stamp_ns, stamp_50);
  EXPECT_TRUE(
      std::equal(right_image.bytes().begin(), right_image.bytes().end(), expected.bytes().begin()))
      << "the right eye rendered another instant than the left";
  // The next cycle moves both eyes on to the newest snapshot.
  ASSERT_EQ(sim.left->grab(left_image), hal::Status::kOk);
  ASSERT_EQ(sim.right->grab(right_image), hal::Status::kOk);
  EXPECT_EQ(left_image.stamp_ns, sim.t_ns);
  EXPECT_EQ(right_image.stamp_ns, sim.t_ns);
  EXPECT_EQ(sim.left->grab(left_image), hal::Status::kNoNewData);
}

}  // namespace
}  // namespace cambio::sim
