#include "test_rig_backend.hpp"

#include <algorithm>
#include <span>
#include <stdexcept>

namespace cambio::testing {
namespace {

/// Ideal drives: kEnable takes a joint to operation enabled at once, holding where it is; an
/// enabled joint is at its (clamped) position target the moment it is written.
class IdealJointGroup final : public hal::JointGroup {
 public:
  IdealJointGroup(const hal::JointGroupInfo& info, const hal::HardwareInfo& hardware,
                  hal::Clock& clock, TestRigRecord& record, double start_offset_rad)
      : info_(info), clock_(clock), record_(record), states_(info.joints.size()) {
    for (std::size_t j = 0; j < info.joints.size(); ++j) {
      states_[j].position_rad =
          hardware.find_joint(info.joints[j])->initial_position_rad + start_offset_rad;
      states_[j].drive_state = hal::DriveState::kSwitchOnDisabled;
    }
  }

  const hal::JointGroupInfo& info() const override { return info_; }

  hal::Status read(std::span<hal::JointState> out, std::int64_t& stamp_ns) override {
    if (out.size() != states_.size()) return hal::Status::kRejected;
    stamp_ns = clock_.now_ns();
    for (std::size_t j = 0; j < states_.size(); ++j) {
      states_[j].stamp_ns = stamp_ns;
      states_[j].status_bits =
          hal::is_enabled(states_[j].drive_state) ? hal::kJointOk : hal::kJointNotEnabled;
      out[j] = states_[j];
    }
    record_.reads.fetch_add(1, std::memory_order_relaxed);
    return hal::Status::kOk;
  }

  hal::Status write(std::span<const hal::JointCommand> commands) override {
    if (commands.size() != states_.size()) return hal::Status::kRejected;
    for (std::size_t j = 0; j < states_.size(); ++j) {
      if (!hal::is_enabled(states_[j].drive_state)) continue;
      hal::JointCommand command = commands[j];
      hal::clamp_command(command, info_.limits[j]);
      if (command.mode == hal::CommandMode::kPosition) states_[j].position_rad = command.value;
    }
    record_.writes.fetch_add(1, std::memory_order_relaxed);
    return hal::Status::kOk;
  }

  hal::Status request(hal::DriveRequest request, int joint) override {
    if (joint != kAllJoints && (joint < 0 || joint >= static_cast<int>(states_.size()))) {
      return hal::Status::kRejected;
    }
    const hal::DriveState next = request == hal::DriveRequest::kEnable
                                     ? hal::DriveState::kOperationEnabled
                                     : hal::DriveState::kSwitchOnDisabled;
    for (std::size_t j = 0; j < states_.size(); ++j) {
      if (joint == kAllJoints || joint == static_cast<int>(j)) states_[j].drive_state = next;
    }
    return hal::Status::kOk;
  }

  void save_positions() const {
    for (std::size_t j = 0; j < states_.size(); ++j) {
      record_.positions_rad[info_.joints[j]] = states_[j].position_rad;
    }
  }

 private:
  hal::JointGroupInfo info_;
  hal::Clock& clock_;
  TestRigRecord& record_;
  std::vector<hal::JointState> states_;
};

/// Hands the group to the run while the backend keeps it, to record its end state.
class GroupHandle final : public hal::JointGroup {
 public:
  explicit GroupHandle(IdealJointGroup& group) : group_(group) {}
  const hal::JointGroupInfo& info() const override { return group_.info(); }
  hal::Status read(std::span<hal::JointState> out, std::int64_t& stamp_ns) override {
    return group_.read(out, stamp_ns);
  }
  hal::Status write(std::span<const hal::JointCommand> commands) override {
    return group_.write(commands);
  }
  hal::Status request(hal::DriveRequest request, int joint) override {
    return group_.request(request, joint);
  }

 private:
  IdealJointGroup& group_;
};

class TestRigBackend final : public hal::Backend {
 public:
  TestRigBackend(const hal::HardwareInfo& hardware, const hal::BackendContext& context,
                 TestRigRecord& record, double start_offset_rad)
      : hardware_(hardware),
        clock_(*context.clock),
        record_(record),
        start_offset_rad_(start_offset_rad) {}

  std::unique_ptr<hal::JointGroup> make_joint_group(std::string_view group_name) override {
    const hal::JointGroupInfo* info = hardware_.find_group(group_name);
    if (info == nullptr) throw std::runtime_error("test_rig: no group " + std::string(group_name));
    groups_.push_back(
        std::make_unique<IdealJointGroup>(*info, hardware_, clock_, record_, start_offset_rad_));
    return std::make_unique<GroupHandle>(*groups_.back());
  }
  std::unique_ptr<hal::Camera> make_camera(std::string_view camera_name) override {
    throw hal::BackendUnavailable("test_rig has no camera '" + std::string(camera_name) + "'");
  }
  std::unique_ptr<hal::TouchSensor> make_touch_sensor(std::string_view sensor_name) override {
    throw hal::BackendUnavailable("test_rig has no touch sensor '" + std::string(sensor_name) +
                                  "'");
  }
  void configure() override { ++record_.configures; }
  void activate() override { ++record_.activates; }
  void deactivate() noexcept override {
    ++record_.deactivates;
    for (const auto& group : groups_) group->save_positions();
  }
  std::vector<hal::BackendLoop> loops() override { return {}; }

 private:
  hal::HardwareInfo hardware_;
  hal::Clock& clock_;
  TestRigRecord& record_;
  double start_offset_rad_;
  std::vector<std::unique_ptr<IdealJointGroup>> groups_;
};

}  // namespace

void register_test_rig_backend(hal::BackendFactory& factory, TestRigRecord& record,
                               double start_offset_rad) {
  factory.register_backend(
      "test_rig", [&record, start_offset_rad](const hal::HardwareInfo& hardware,
                                              const hal::BackendContext& context) {
        return std::unique_ptr<hal::Backend>(
            std::make_unique<TestRigBackend>(hardware, context, record, start_offset_rad));
      });
}

}  // namespace cambio::testing
