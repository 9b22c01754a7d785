// The real CANopen master (the socketcan backend and its CanJointGroup) against the real virtual
// rig (emulated CiA 402 drives on the sim's servo model), made for the shipped pan-tilt rig with
// its group switched to socketcan, on one in-process bus with a manual clock, stepped in one
// thread: configure, enable, CSP motion, faults and recovery, deactivate. The host counterpart of
// the guest's master <-> virtual rig test; the truth is the emulated drives' own state and the
// servo model's limits.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <vector>

#include "cambio/can/in_process_can_bus.hpp"
#include "cambio/canopen/can_rig_from_config.hpp"
#include "cambio/canopen/cia402.hpp"
#include "cambio/canopen/protocol.hpp"
#include "cambio/canopen/socketcan_backend.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/virtual_rig/virtual_rig.hpp"
#include "master_and_rig.hpp"

namespace cambio::virtual_rig::test {
namespace {

/// The drive's own view of the heartbeat period the master configured (0x1017, ms).
std::int64_t heartbeat_period_ns(const EmulatedDrive& drive) {
  return static_cast<std::int64_t>(drive.dictionary().get({canopen::kProducerHeartbeatTime, 0})) *
         1'000'000;
}

TEST(MasterVirtualRig, ConfigureWritesTheRigsParametersIntoTheDrives) {
  MasterAndRig m;
  m.start();
  for (std::size_t k = 0; k < 2; ++k) {
    const EmulatedDrive& drive = m.drive(k);
    const config::JointConfig& joint = *m.rig.find_joint(m.drives->joint_name(0, k));
    const ObjectDictionary& od = drive.dictionary();
    SCOPED_TRACE(joint.name);
    EXPECT_EQ(drive.nmt_state(), canopen::NmtState::kOperational);
    EXPECT_EQ(drive.drive_state(), hal::DriveState::kSwitchOnDisabled);
    // The rig's limits in the drive's counts: gear 50, 4096 counts per motor turn.
    const double counts_per_rad = 50.0 * 4096.0 / (2.0 * std::numbers::pi);
    EXPECT_EQ(od.get_signed(canopen::cia402::kMinSoftwarePositionLimit),
              std::lround(joint.min_position_rad * counts_per_rad));
    EXPECT_EQ(od.get_signed(canopen::cia402::kMaxSoftwarePositionLimit),
              std::lround(joint.max_position_rad * counts_per_rad));
    EXPECT_EQ(od.get(canopen::cia402::kMaxProfileVelocity),
              static_cast<std::uint32_t>(std::lround(joint.max_velocity_rad_s * counts_per_rad)));
    EXPECT_EQ(od.get(canopen::cia402::kModesOfOperation), 8u) << "CSP";
    EXPECT_EQ(heartbeat_period_ns(drive), 100'000'000) << "the rig's default 100 ms";
    EXPECT_EQ(od.get(canopen::cia402::kInterpolationTimePeriod), 1u) << "1 kHz = 1 * 10^-3 s";
    EXPECT_EQ(od.get_signed(canopen::cia402::kInterpolationTimeIndex), -3);
    // CiA 301 PDO objects: RPDO1 controlword + target position, TPDO1 statusword + position.
    const auto node = static_cast<std::uint32_t>(drive.node_id());
    EXPECT_EQ(od.get({0x1400, 1}), 0x200u + node);
    EXPECT_EQ(od.get({0x1600, 0}), 2u);
    EXPECT_EQ(od.get({0x1600, 1}), 0x6040'0010u);
    EXPECT_EQ(od.get({0x1600, 2}), 0x607A'0020u);
    // Valid (bit 31 clear); bit 30, "no RTR", is the master's choice.
    EXPECT_EQ(od.get({0x1800, 1}) & ~0x4000'0000u, 0x180u + node);
    EXPECT_EQ(od.get({0x1800, 2}), 1u) << "synchronous, every SYNC";
    EXPECT_EQ(od.get({0x1A00, 0}), 2u);
    EXPECT_EQ(od.get({0x1A00, 1}), 0x6041'0010u);
    EXPECT_EQ(od.get({0x1A00, 2}), 0x6064'0020u);
  }
}

TEST(MasterVirtualRig, EnableFollowACspTrajectoryDisableDeactivate) {
  MasterAndRig m;
  m.start();
  ASSERT_EQ(m.cycle(), hal::Status::kOk);
  const std::vector<double> start_rad = {m.drive(0).servo().output_position_rad(),
                                         m.drive(1).servo().output_position_rad()};
  const std::vector<hal::JointCommand> hold = m.hold_here();
  const int enable_cycles = m.enable(hold);
  ASSERT_GT(enable_cycles, 0) << "operation enabled within 20 cycles";
  // Three transitions (switch on disabled -> ready -> switched on -> enabled), each a controlword
  // out with one SYNC and the statusword back with the next, and the cycle that reads the last.
  EXPECT_LE(enable_cycles, 3 * 2 + 1);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(m.drive(k).drive_state(), hal::DriveState::kOperationEnabled);
    // Enabled where it stood: within a bus count of the measured position, no jump.
    EXPECT_NEAR(m.drive(k).servo().output_position_rad(), start_rad[k],
                m.drive(k).units().to_rad(1) + 1e-12);
    EXPECT_EQ(m.states[k].status_bits & hal::kJointNotEnabled, 0u);
  }

  // q(t) = q0 + A (1 - cos(w t)): starts at rest, peak velocity A w, peak acceleration A w^2,
  // both well inside the joints' 3 rad/s and 30 rad/s^2, positions inside both joints' limits.
  const double amplitude_rad = 0.3;
  const double omega_rad_s = std::numbers::pi;  // 0.5 Hz.
  const double duration_s = 2.0;
  const double period_s = static_cast<double>(m.period_ns) * 1e-9;
  const sim::ServoParams& servo = m.drive(0).servo().params();
  const double v_max = amplitude_rad * omega_rad_s;
  ASSERT_LT(v_max, servo.max_velocity_rad_s);
  ASSERT_LT(amplitude_rad * omega_rad_s * omega_rad_s, servo.max_acceleration_rad_s2);

  // The tracking error bound, from the servo model and the cycle (not tuned):
  // - delay: the target written at cycle k goes out with SYNC k, is latched by the drive on that
  //   SYNC, enters the servo's delay line on its next step, runs after dead_time_s; the position
  //   read at cycle k was sampled at SYNC k-1. Reference to reading: one cycle + dead time + two
  //   servo steps (command queue, profile step).
  // - the profile's own lag behind a target moving at v: it approaches only as fast as it can
  //   still stop (ServoModel::advance_position_profile), v <= n a dt with
  //   n = sqrt(1/4 + 2|e|/(a dt^2)) - 1/2, so |e| <= a dt^2 (v/(a dt) + 1/2)^2 / 2, plus one step
  //   of the target's motion (the |e|/dt cap).
  // - noise and quantisation: 6 sigma of motion noise, one servo encoder count, one bus count.
  const double dt = servo.step_s;
  const double a = servo.max_acceleration_rad_s2;
  const double delay_s = period_s + servo.dead_time_s + 2.0 * dt;
  const double profile_lag_rad =
      a * dt * dt * std::pow(v_max / (a * dt) + 0.5, 2) / 2.0 + v_max * dt;
  const double noise_rad =
      6.0 * servo.motion_noise_std_rad +
      2.0 * std::numbers::pi / static_cast<double>(servo.encoder_counts_per_rev) +
      m.drive(0).units().to_rad(1);
  const double bound_rad = v_max * delay_s + profile_lag_rad + noise_rad;

  const auto cycles = static_cast<int>(std::lround(duration_s / period_s));
  std::vector<hal::JointCommand> commands = hold;
  std::vector<double> max_error_rad(2, 0.0), sum_sq_rad2(2, 0.0), max_travel_rad(2, 0.0);
  for (int i = 0; i < cycles; ++i) {
    const double t_s = static_cast<double>(i) * period_s;
    ASSERT_EQ(m.cycle(&commands), hal::Status::kOk) << "cycle " << i;
    for (std::size_t k = 0; k < 2; ++k) {
      // The reading against the reference commanded this cycle; the master's reading against
      // what the drive's encoder says (one bus count).
      const double error_rad = commands[k].value - m.states[k].position_rad;
      max_error_rad[k] = std::max(max_error_rad[k], std::abs(error_rad));
      sum_sq_rad2[k] += error_rad * error_rad;
      max_travel_rad[k] = std::max(max_travel_rad[k], m.states[k].position_rad - hold[k].value);
      EXPECT_EQ(m.states[k].status_bits & (hal::kJointLatchingBits | hal::kJointStale), 0u);
      commands[k].value =
          hold[k].value + amplitude_rad * (1.0 - std::cos(omega_rad_s * (t_s + period_s)));
    }
  }
  for (std::size_t k = 0; k < 2; ++k) {
    const double rms_rad = std::sqrt(sum_sq_rad2[k] / cycles);
    std::printf("joint %zu: tracking error max %.5f rad, rms %.5f rad, bound %.5f rad\n", k,
                max_error_rad[k], rms_rad, bound_rad);
    EXPECT_LE(max_error_rad[k], bound_rad) << "joint " << k;
    // The motion really happened: the joint went out the full 2 A.
    EXPECT_GE(max_travel_rad[k], 2.0 * amplitude_rad - bound_rad) << "joint " << k;
    EXPECT_EQ(m.drive(k).drive_state(), hal::DriveState::kOperationEnabled);
  }
  const auto counters = m.backend->group("pan_tilt")->counters();
  EXPECT_EQ(counters.missed_sync_answers, 0u);
  EXPECT_EQ(counters.late_tpdos, 0u);
  EXPECT_EQ(counters.malformed_frames, 0u);
  EXPECT_EQ(counters.unexpected_frames, 0u);

  // Disable through the group: switch on disabled, torque off.
  ASSERT_EQ(m.group->request(hal::DriveRequest::kDisable), hal::Status::kOk);
  const std::vector<hal::JointCommand> here = m.hold_here();
  for (int i = 0; i < 5; ++i) (void)m.cycle(&here);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(m.drive(k).drive_state(), hal::DriveState::kSwitchOnDisabled);
    EXPECT_NE(m.states[k].status_bits & hal::kJointNotEnabled, 0u);
  }

  // Enabled again for deactivate() to have something to stop.
  ASSERT_GT(m.enable(m.hold_here()), 0);
  m.backend->deactivate();
  m.let_drives_answer();
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(m.drive(k).drive_state(), hal::DriveState::kSwitchOnDisabled);
    EXPECT_EQ(m.drive(k).nmt_state(), canopen::NmtState::kPreOperational);
  }
}

/// Cycles with `commands` until read() reports `bit` on `joint`; returns the time that took from
/// `since_ns`, or nullopt after `max_cycles`.
std::optional<std::int64_t> cycles_until(MasterAndRig& m, std::size_t joint, std::uint32_t bit,
                                         const std::vector<hal::JointCommand>& commands,
                                         std::int64_t since_ns, int max_cycles) {
  for (int i = 0; i < max_cycles; ++i) {
    (void)m.cycle(&commands);
    if ((m.states[joint].status_bits & bit) != 0) return m.clock.now_ns() - since_ns;
  }
  return std::nullopt;
}

/// Every RPDO1 the master sent from `first` on: no enable-operation controlword, and the target
/// is the position the drive last reported in its TPDO1 (nothing that moves a joint).
void expect_no_motion_commands(const MasterAndRig& m, std::size_t first) {
  std::array<std::optional<std::int32_t>, 128> reported{};
  std::size_t rpdos = 0;
  for (std::size_t i = 0; i < m.sent.size(); ++i) {
    const hal::CanFrame& frame = m.sent[i].frame;
    const auto node = static_cast<std::size_t>(canopen::node_of(frame.id));
    if (m.sent[i].received && canopen::function_of(frame.id) == 0x180) {
      reported[node] = static_cast<std::int32_t>(canopen::get_le(frame.data, 2, 4));
    }
    if (i < first || m.sent[i].received || canopen::function_of(frame.id) != 0x200) continue;
    ++rpdos;
    const auto controlword = static_cast<std::uint16_t>(canopen::get_le(frame.data, 0, 2));
    const auto target = static_cast<std::int32_t>(canopen::get_le(frame.data, 2, 4));
    EXPECT_NE(controlword & 0x000F, 0x000F) << "enable operation after the fault, frame " << i;
    ASSERT_TRUE(reported[node].has_value());
    EXPECT_EQ(target, *reported[node]) << "a target other than the measured position, frame " << i;
  }
  EXPECT_GT(rpdos, 0u);
}

TEST(MasterVirtualRig, FollowingErrorIsLatchedHeldAndRecoveredWithoutAJump) {
  MasterAndRig m;
  m.start();
  (void)m.cycle();
  const std::vector<hal::JointCommand> hold = m.hold_here();
  ASSERT_GT(m.enable(hold), 0);
  // A 0.5 rad step on pan: 0.1 s into the move the drive runs at its 3 rad/s, its demand far
  // ahead; the fault makes it brake to a stop well short of that demand, so a re-enable that
  // went on to the old demand would jump.
  std::vector<hal::JointCommand> commands = hold;
  commands[0].value = hold[0].value + 0.5;
  for (int i = 0; i < 100; ++i) ASSERT_EQ(m.cycle(&commands), hal::Status::kOk);

  FaultInjection fault;
  fault.kind = FaultKind::kFollowingError;
  fault.node_id = 1;
  fault.at_s = m.seconds_since_power_on();
  ASSERT_TRUE(m.drive(0).schedule(fault));
  const std::int64_t injected_ns = m.clock.now_ns();
  const std::int64_t heartbeat_ns = heartbeat_period_ns(m.drive(0));
  const auto latched = cycles_until(m, 0, hal::kJointFault, commands, injected_ns, 400);
  ASSERT_TRUE(latched.has_value()) << "fault never reported";
  EXPECT_LE(*latched, 3 * heartbeat_ns);
  EXPECT_EQ(m.states[0].error_code, 0x8611) << "EMCY following error";
  // From the read that saw the fault on, nothing moves: the healthy drive quick-stops.
  const std::size_t sent_after_fault = m.sent_at_read;
  for (int i = 0; i < 200; ++i) (void)m.cycle(&commands);
  EXPECT_NE(m.states[0].status_bits & hal::kJointFault, 0u) << "latched until a reset";
  EXPECT_EQ(m.drive(0).drive_state(), hal::DriveState::kFault);
  EXPECT_EQ(m.drive(1).drive_state(), hal::DriveState::kQuickStopActive);
  expect_no_motion_commands(m, sent_after_fault);
  const double stopped_rad = m.drive(0).servo().output_position_rad();
  EXPECT_GT(std::abs(commands[0].value - stopped_rad), 0.1) << "braked short of the old demand";

  // Fault reset, then enable, holding where the joints are measured.
  ASSERT_EQ(m.group->request(hal::DriveRequest::kFaultReset), hal::Status::kOk);
  for (int i = 0; i < 5; ++i) (void)m.cycle(&commands);
  EXPECT_EQ(m.states[0].status_bits & hal::kJointLatchingBits, 0u);
  EXPECT_EQ(m.states[0].error_code, 0u) << "EMCY 0x0000 after the reset";
  const std::vector<hal::JointCommand> here = m.hold_here();
  ASSERT_GT(m.enable(here), 0);
  for (int i = 0; i < 50; ++i) ASSERT_EQ(m.cycle(&here), hal::Status::kOk);
  // Holding the measured position moves the joint by what measuring it loses: one servo encoder
  // count, one bus count, and the servo's motion noise (6 sigma) on the step it takes.
  const sim::ServoParams& servo = m.drive(0).servo().params();
  const double tolerance_rad =
      2.0 * std::numbers::pi / static_cast<double>(servo.encoder_counts_per_rev) +
      m.drive(0).units().to_rad(1) + 6.0 * servo.motion_noise_std_rad;
  EXPECT_NEAR(m.drive(0).servo().output_position_rad(), stopped_rad, tolerance_rad)
      << "re-enabled where it stopped, not at the old demand";
  EXPECT_EQ(m.drive(0).drive_state(), hal::DriveState::kOperationEnabled);
  EXPECT_EQ(m.drive(1).drive_state(), hal::DriveState::kOperationEnabled);
}

TEST(MasterVirtualRig, ASilentDriveIsLostWithinThreeHeartbeatPeriods) {
  MasterAndRig m;
  m.start();
  (void)m.cycle();
  const std::vector<hal::JointCommand> hold = m.hold_here();
  ASSERT_GT(m.enable(hold), 0);
  for (int i = 0; i < 150; ++i) (void)m.cycle(&hold);

  FaultInjection fault;
  fault.kind = FaultKind::kHeartbeatStop;
  fault.node_id = 2;
  fault.at_s = m.seconds_since_power_on();
  ASSERT_TRUE(m.drive(1).schedule(fault));
  const std::int64_t injected_ns = m.clock.now_ns();
  const std::int64_t heartbeat_ns = heartbeat_period_ns(m.drive(1));
  const auto lost = cycles_until(m, 1, hal::kJointCommLost, hold, injected_ns, 1000);
  ASSERT_TRUE(lost.has_value()) << "loss never reported";
  EXPECT_LE(*lost, 3 * heartbeat_ns);
  EXPECT_EQ(m.states[0].status_bits & hal::kJointCommLost, 0u) << "only the silent node";
  const std::size_t sent_after_loss = m.sent_at_read;
  for (int i = 0; i < 10; ++i) (void)m.cycle(&hold);
  EXPECT_EQ(m.drive(0).drive_state(), hal::DriveState::kQuickStopActive) << "group held";
  EXPECT_EQ(m.drive(1).drive_state(), hal::DriveState::kQuickStopActive)
      << "the silent drive still listens";
  expect_no_motion_commands(m, sent_after_loss);
}

}  // namespace
}  // namespace cambio::virtual_rig::test
