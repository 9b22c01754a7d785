// Mixed rigs: the sim's world follows groups another backend drives, so its cameras see what
// those drives did; and the real loops stay allocation-free through every drive transition.
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cambio/hal/joint_state_tap.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/runtime/loop_statistics.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "lockstep_sim.hpp"
#include "sim_test_support.hpp"

namespace cambio::sim {
namespace {

/// A group "another backend" drives: it reports the positions the test scripts, enabled.
class ScriptedGroup final : public hal::JointGroup {
 public:
  explicit ScriptedGroup(const hal::JointGroupInfo& info)
      : positions_rad(info.joints.size(), 0.0), info_(info) {}

  const hal::JointGroupInfo& info() const override { return info_; }
  hal::Status read(std::span<hal::JointState> out, std::int64_t& stamp_ns) override {
    if (out.size() != positions_rad.size()) return hal::Status::kRejected;
    for (std::size_t k = 0; k < out.size(); ++k) {
      out[k] = hal::JointState{};
      out[k].position_rad = positions_rad[k];
      out[k].stamp_ns = now_ns;
      out[k].drive_state = hal::DriveState::kOperationEnabled;
    }
    stamp_ns = now_ns;
    return hal::Status::kOk;
  }
  hal::Status write(std::span<const hal::JointCommand>) override { return hal::Status::kOk; }
  hal::Status request(hal::DriveRequest, int) override { return hal::Status::kOk; }

  std::vector<double> positions_rad;
  std::int64_t now_ns = 0;

 private:
  hal::JointGroupInfo info_;
};

/// Has the leader's readings published, as the joint loop's read() through the tap does.
void publish(hal::JointStateTap& tap) {
  std::vector<hal::JointState> states(tap.info().joints.size());
  std::int64_t stamp = 0;
  ASSERT_EQ(tap.read(states, stamp), hal::Status::kOk);
}

void expect_same_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                      const std::string& what) {
  EXPECT_LT((a.translation() - b.translation()).norm(), 1e-12) << what;
  EXPECT_LT((a.linear() - b.linear()).norm(), 1e-12) << what;
}

TEST(SimFollowTest, TheHeadFollowsTheDrivesReportedPositionsAndTheEyesSeeIt) {
  auto rig = testing::load_shipped_rig();
  testing::make_ideal(rig);
  testing::use_small_cameras(rig);
  testing::set_group_backend(rig, "head", "socketcan");
  const hal::HardwareInfo hardware = config::hardware_description(rig);
  const hal::JointGroupInfo& head = *hardware.find_group("head");
  hal::ManualClock clock;
  // The world still holds every joint of the rig; only a sim group of the head is refused.
  auto backend = testing::make_sim(rig, testing::load_shipped_scene("vergence"), clock);
  try {
    (void)backend->make_joint_group("head");
    FAIL() << "made a sim group of a socketcan group";
  } catch (const hal::BackendUnavailable& error) {
    EXPECT_NE(std::string(error.what()).find("socketcan"), std::string::npos) << error.what();
  }
  ScriptedGroup drives(head);
  hal::JointStateTap tap(drives);
  backend->follow_group(head, tap);
  try {
    (void)backend->make_joint_group("head");
    FAIL() << "made a sim group of a followed group";
  } catch (const hal::BackendUnavailable& error) {
    EXPECT_NE(std::string(error.what()).find("followed"), std::string::npos) << error.what();
  }
  EXPECT_THROW(backend->follow_group(head, tap), hal::BackendUnavailable) << "one leader";
  auto arm = backend->make_joint_group("left_arm");  // The other groups stay the sim's.
  auto left = backend->make_camera("left_eye");
  backend->configure();
  backend->activate();

  // Until the leader publishes, the head stays where it is.
  ASSERT_EQ(backend->physics().step_once(1'000'000), hal::Status::kOk);
  for (const auto& joint : head.joints) {
    EXPECT_EQ(backend->ground_truth().joint_position_rad(joint), 0.0) << joint;
  }

  drives.positions_rad = {0.2, -0.1, 0.15, 0.05, -0.08};
  drives.now_ns = 1'500'000;
  publish(tap);
  ASSERT_EQ(backend->physics().step_once(2'000'000), hal::Status::kOk);
  for (std::size_t k = 0; k < head.joints.size(); ++k) {
    EXPECT_EQ(backend->ground_truth().joint_position_rad(head.joints[k]), drives.positions_rad[k])
        << head.joints[k] << " is where its drive says, after one step";
  }
  // The eyes are where a sim started at those positions puts them, and see what it sees.
  auto probe_rig = rig;
  for (std::size_t k = 0; k < head.joints.size(); ++k) {
    testing::set_initial(probe_rig, head.joints[k], drives.positions_rad[k]);
  }
  testing::set_group_backend(probe_rig, "head", "sim");
  auto probe = testing::make_sim(probe_rig, testing::load_shipped_scene("vergence"), clock);
  auto probe_left = probe->make_camera("left_eye");
  probe->activate();
  for (const char* eye : {"left_eye", "right_eye"}) {
    expect_same_pose(backend->ground_truth().X_WC(eye), probe->ground_truth().X_WC(eye), eye);
  }
  const auto& k = left->info().intrinsics;
  hal::Image seen(k.width_px, k.height_px, left->info().format);
  hal::Image expected(k.width_px, k.height_px, left->info().format);
  ASSERT_EQ(left->grab(seen), hal::Status::kOk);
  ASSERT_EQ(probe_left->grab(expected), hal::Status::kOk);
  EXPECT_EQ(seen.stamp_ns, 2'000'000);
  EXPECT_TRUE(std::equal(seen.bytes().begin(), seen.bytes().end(), expected.bytes().begin()))
      << "the left eye's image is the one a sim at the drives' positions renders";

  // It keeps following.
  drives.positions_rad = {-0.3, 0.2, -0.1, 0.0, 0.1};
  publish(tap);
  ASSERT_EQ(backend->physics().step_once(3'000'000), hal::Status::kOk);
  for (std::size_t j = 0; j < head.joints.size(); ++j) {
    EXPECT_EQ(backend->ground_truth().joint_position_rad(head.joints[j]), drives.positions_rad[j]);
  }
}

TEST(SimFollowTest, AnArmDrivenElsewhereIsFollowedThroughPhysicsWithItsTouchSensor) {
  auto rig = testing::load_shipped_rig();
  testing::make_ideal(rig);
  testing::set_group_backend(rig, "left_arm", "socketcan");
  const hal::HardwareInfo hardware = config::hardware_description(rig);
  const hal::JointGroupInfo& arm = *hardware.find_group("left_arm");
  hal::ManualClock clock;
  auto backend = testing::make_sim(rig, testing::empty_scene(), clock);
  ScriptedGroup drives(arm);
  hal::JointStateTap tap(drives);
  backend->follow_group(arm, tap);
  auto hand = backend->make_touch_sensor("left_hand");
  backend->configure();
  backend->activate();
  drives.positions_rad = {0.3, 0.4, 0.8, -0.3, 0.2};
  publish(tap);
  for (int step = 1; step <= 2'000; ++step) {
    ASSERT_EQ(backend->physics().step_once(step * 1'000'000LL), hal::Status::kOk);
  }
  for (std::size_t k = 0; k < arm.joints.size(); ++k) {
    EXPECT_NEAR(backend->ground_truth().joint_position_rad(arm.joints[k]), drives.positions_rad[k],
                5e-3)
        << arm.joints[k] << " tracks its drive under gravity";
  }
}

TEST(SimFollowTest, ConfigureRefusesADeviceHangingFromAGroupNoOneMoves) {
  auto rig = testing::load_shipped_rig();
  testing::use_small_cameras(rig);
  testing::set_group_backend(rig, "head", "socketcan");
  testing::set_group_backend(rig, "left_arm", "socketcan");
  hal::ManualClock clock;
  {
    auto backend = testing::make_sim(rig, testing::empty_scene(), clock);
    auto left = backend->make_camera("left_eye");
    try {
      backend->configure();
      FAIL() << "accepted a camera on a head no one moves";
    } catch (const std::runtime_error& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("'left_eye'"), std::string::npos) << message;
      EXPECT_NE(message.find("'head'"), std::string::npos) << message;
      EXPECT_NE(message.find("follow"), std::string::npos) << message;
    }
  }
  auto backend = testing::make_sim(rig, testing::empty_scene(), clock);
  auto hand = backend->make_touch_sensor("left_hand");
  EXPECT_THROW(backend->configure(), std::runtime_error);
}

TEST(SimFollowTest, AGroupTheSimDrivesCannotBeFollowed) {
  const auto rig = testing::load_shipped_rig();
  const hal::HardwareInfo hardware = config::hardware_description(rig);
  hal::ManualClock clock;
  auto backend = testing::make_sim(rig, testing::empty_scene(), clock);
  ScriptedGroup drives(*hardware.find_group("head"));
  hal::JointStateTap tap(drives);
  EXPECT_THROW(backend->follow_group(*hardware.find_group("head"), tap), hal::BackendUnavailable);
  auto arm = backend->make_joint_group("left_arm");
  EXPECT_THROW(backend->follow_group(*hardware.find_group("left_arm"), tap),
               hal::BackendUnavailable);
  hal::JointGroupInfo unknown;
  unknown.name = "tail";
  EXPECT_THROW(backend->follow_group(unknown, tap), hal::BackendUnavailable);
}

/// The other backend's side of a mixed rig: the head's drives move along sines and the tap
/// publishes what they report, as the joint loop's read() of a CAN group would.
class LeaderLoop final : public hal::Loop {
 public:
  explicit LeaderLoop(ScriptedGroup& drives)
      : drives_(drives), tap_(drives), states_(drives.info().joints.size()) {}
  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    const double t = static_cast<double>(tick.deadline_ns) * 1e-9;
    for (std::size_t k = 0; k < drives_.positions_rad.size(); ++k) {
      drives_.positions_rad[k] = 0.1 * std::sin(2.0 * t + static_cast<double>(k));
    }
    drives_.now_ns = tick.now_ns;
    std::int64_t stamp = 0;
    return tap_.read(states_, stamp);
  }
  hal::JointStateTap& tap() { return tap_; }

 private:
  std::string name_ = "leader";
  ScriptedGroup& drives_;
  hal::JointStateTap tap_;
  std::vector<hal::JointState> states_;
};

/// The sim arm's joint loop taking every drive through each lifecycle state and fault hook.
class LifecycleLoop final : public hal::Loop {
 public:
  LifecycleLoop(SimBackend& backend, std::unique_ptr<hal::JointGroup> group)
      : backend_(backend),
        group_(std::move(group)),
        states_(group_->info().joints.size()),
        commands_(group_->info().joints.size()) {}
  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    std::int64_t stamp = 0;
    (void)group_->read(states_, stamp);  // kFault while a drive is faulted: expected here.
    for (const auto& state : states_) {
      seen_states_ |= 1u << static_cast<unsigned>(state.drive_state);
      seen_bits_ |= state.status_bits;
    }
    using R = hal::DriveRequest;
    hal::Status status = hal::Status::kOk;
    switch (tick.cycle) {
      case 0:
        status = group_->request(R::kEnable);
        break;
      case 200:
        status = group_->request(R::kQuickStop);
        break;
      case 300:
        status = group_->request(R::kEnable);
        break;
      case 400:
        backend_.inject_fault("left_wrist", 0x5530);
        break;
      case 500:
        status = group_->request(R::kFaultReset, 3);
        break;
      case 550:
        status = group_->request(R::kEnable);
        break;
      case 600:
        backend_.inject_comm_loss("left_elbow");
        break;
      case 700:
        status = group_->request(R::kFaultReset);
        break;
      case 750:
        status = group_->request(R::kEnable);
        break;
      case 800:
        backend_.freeze_feedback("left_shoulder_yaw", true);
        break;
      case 850:
        backend_.freeze_feedback("left_shoulder_yaw", false);
        break;
      case 900:
        status = group_->request(R::kDisable);
        break;
      default:
        break;
    }
    const double t = static_cast<double>(tick.deadline_ns) * 1e-9;
    for (std::size_t k = 0; k < commands_.size(); ++k) {
      const auto& limits = group_->info().limits[k];
      const double middle = 0.5 * (limits.min_position_rad + limits.max_position_rad);
      commands_[k].value = middle + 0.2 * std::sin(3.0 * t + static_cast<double>(k));
      commands_[k].effort_feedforward_nm = 0.01;
    }
    return hal::worst(status, group_->write(commands_));
  }
  std::uint32_t seen_states() const { return seen_states_; }
  std::uint32_t seen_bits() const { return seen_bits_; }

 private:
  std::string name_ = "joint";
  SimBackend& backend_;
  std::unique_ptr<hal::JointGroup> group_;
  std::vector<hal::JointState> states_;
  std::vector<hal::JointCommand> commands_;
  std::uint32_t seen_states_ = 0;
  std::uint32_t seen_bits_ = 0;
};

class StereoGrabLoop final : public hal::Loop {
 public:
  StereoGrabLoop(std::unique_ptr<hal::Camera> left, std::unique_ptr<hal::Camera> right)
      : left_(std::move(left)), right_(std::move(right)) {
    const auto& k = left_->info().intrinsics;
    left_image_.resize(k.width_px, k.height_px, left_->info().format);
    right_image_.resize(k.width_px, k.height_px, right_->info().format);
  }
  const std::string& name() const override { return name_; }
  bool allocates_in_update() const override {
    return left_->grab_allocates() || right_->grab_allocates();
  }
  hal::Status update(const hal::LoopTick&) noexcept override {
    const hal::Status status = hal::worst(left_->grab(left_image_), right_->grab(right_image_));
    if (left_image_.stamp_ns != right_image_.stamp_ns) return hal::Status::kFault;
    return status;
  }

 private:
  std::string name_ = "camera";
  std::unique_ptr<hal::Camera> left_, right_;
  hal::Image left_image_, right_image_;
};

TEST(SimLoopsTest, EveryDriveTransitionFaultAndFollowRunWithoutAllocating) {
  auto rig = testing::load_shipped_rig();
  testing::use_small_cameras(rig);
  testing::set_group_backend(rig, "head", "socketcan");
  const hal::HardwareInfo hardware = config::hardware_description(rig);
  ScriptedGroup drives(*hardware.find_group("head"));
  LeaderLoop leader(drives);
  testing::LockstepSim sim(rig, testing::load_shipped_scene("distractors"), 3);
  sim.backend->follow_group(*hardware.find_group("head"), leader.tap());
  LifecycleLoop joint_loop(*sim.backend, sim.backend->make_joint_group("left_arm"));
  StereoGrabLoop camera_loop(sim.backend->make_camera("left_eye"),
                             sim.backend->make_camera("right_eye"));
  sim.add_loop(leader, 1000.0);
  sim.add_loop(joint_loop, 1000.0);
  sim.add_loop(camera_loop, 30.0);
  sim.start();
  sim.run_for_s(1.0);
  sim.stop();

  using S = hal::DriveState;
  for (const S state :
       {S::kSwitchOnDisabled, S::kReadyToSwitchOn, S::kSwitchedOn, S::kOperationEnabled,
        S::kQuickStopActive, S::kFaultReactionActive, S::kFault}) {
    EXPECT_TRUE(joint_loop.seen_states() & (1u << static_cast<unsigned>(state)))
        << "the run never showed " << hal::to_string(state);
  }
  for (const std::uint32_t bit : {hal::kJointFault, hal::kJointCommLost, hal::kJointNotEnabled}) {
    EXPECT_TRUE(joint_loop.seen_bits() & bit) << "status bit " << bit;
  }
  // The last physics step ran before the leader's last cycle (same instant, physics first):
  // within one cycle of the drives' motion (0.2 rad/s at most).
  for (std::size_t k = 0; k < drives.positions_rad.size(); ++k) {
    EXPECT_NEAR(sim.backend->ground_truth().joint_position_rad(drives.info().joints[k]),
                drives.positions_rad[k], 0.2 * 1e-3 + 1e-12)
        << "the head ends where its drives are";
  }
  // The physics step allocates nothing; rendering allocates in Mesa, and the cameras say so.
  for (const auto& stats : sim.executor.statistics()) {
    if (stats.name == "physics" || stats.name == "camera") {
      EXPECT_TRUE(runtime::passes_allocation_gate(stats)) << stats.name << " allocated";
      EXPECT_EQ(stats.allocation_exempt, stats.name == "camera") << stats.name;
      EXPECT_EQ(stats.failed_updates, 0u) << stats.name << ": " << stats.fault_message;
      EXPECT_GT(stats.cycles, 0u) << stats.name;
    }
  }
}

}  // namespace
}  // namespace cambio::sim
