// The emulated CiA 402 drive on the bus: NMT and heartbeat, PDO configuration per CiA 301, CSP
// motion against the sim's servo model alone, and every fault injection seen on the bus.
#include <cmath>

#include "cambio/runtime/allocation_counter.hpp"
#include "drive_test_support.hpp"

namespace cambio::virtual_rig::test {
namespace {

constexpr std::int64_t kMs = 1'000'000;

TEST(EmulatedDrive, BootsUpAndProducesItsHeartbeatOnTime) {
  DriveBench bench;
  bench.power_on();
  ASSERT_EQ(bench.log().size(), 1u);
  EXPECT_EQ(bench.log()[0].id, 0x703u);
  EXPECT_EQ(bench.log()[0].length, 1);
  EXPECT_EQ(bench.log()[0].data[0], 0x00) << "boot-up";
  EXPECT_EQ(bench.drive().nmt_state(), canopen::NmtState::kPreOperational);

  EXPECT_TRUE(bench.advance_to_ns(99 * kMs).empty());
  auto beat = bench.advance_to_ns(100 * kMs);
  ASSERT_EQ(beat.size(), 1u);
  EXPECT_EQ(beat[0].id, 0x703u);
  EXPECT_EQ(beat[0].data[0], 0x7F) << "pre-operational";
  EXPECT_EQ(bench.drive().next_event_ns(), 200 * kMs);

  bench.nmt(0x01);  // Start.
  EXPECT_EQ(bench.drive().nmt_state(), canopen::NmtState::kOperational);
  beat = bench.advance_to_ns(200 * kMs);
  ASSERT_EQ(beat.size(), 1u);
  EXPECT_EQ(beat[0].data[0], 0x05) << "operational";

  // 0x1017 rewritten: the next heartbeat is one new period after the write.
  bench.advance_to_ns(210 * kMs);
  EXPECT_EQ(bench.write(0x1017, 0, 50, 2), 0u);
  EXPECT_TRUE(bench.advance_to_ns(259 * kMs).empty());
  EXPECT_EQ(with_id(bench.advance_to_ns(260 * kMs), 0x703).size(), 1u);

  bench.nmt(0x02, 0);  // Stop, broadcast.
  beat = bench.advance_to_ns(310 * kMs);
  ASSERT_EQ(beat.size(), 1u);
  EXPECT_EQ(beat[0].data[0], 0x04) << "stopped";
}

TEST(EmulatedDrive, HeartbeatOffWhenZero) {
  DriveBench bench;
  bench.power_on();
  EXPECT_EQ(bench.write(0x1017, 0, 0, 2), 0u);
  EXPECT_TRUE(bench.advance_to_ns(1000 * kMs).empty());
}

TEST(EmulatedDrive, ResetCommunicationRestoresCommunicationObjectsOnly) {
  DriveBench bench;
  bench.power_on();
  EXPECT_EQ(bench.write(0x1017, 0, 20, 2), 0u);
  EXPECT_EQ(bench.write(0x6065, 0, 777, 4), 0u);
  auto frames = bench.nmt(0x82);
  ASSERT_EQ(with_id(frames, 0x703).size(), 1u);
  EXPECT_EQ(with_id(frames, 0x703)[0].data[0], 0x00) << "boot-up again";
  EXPECT_EQ(bench.upload(0x1017, 0).value, 100u);
  EXPECT_EQ(bench.upload(0x6065, 0).value, 777u);
  frames = bench.nmt(0x81);  // Reset node: everything.
  EXPECT_EQ(with_id(frames, 0x703).size(), 1u);
  EXPECT_EQ(bench.upload(0x6065, 0).value, 0xFFFFFFFFu);
  EXPECT_EQ(bench.drive().nmt_state(), canopen::NmtState::kPreOperational);
}

TEST(EmulatedDrive, NmtForAnotherNodeIsIgnored) {
  DriveBench bench;
  bench.power_on();
  bench.nmt(0x01, 9);
  EXPECT_EQ(bench.drive().nmt_state(), canopen::NmtState::kPreOperational);
  bench.exchange({frame(0x000, {0x01})});  // One byte: malformed.
  EXPECT_EQ(bench.drive().nmt_state(), canopen::NmtState::kPreOperational);
  EXPECT_EQ(bench.drive().counters().malformed_frames, 1u);
}

TEST(EmulatedDrive, PdosOnlyInOperational) {
  DriveBench bench;
  bench.power_on();
  EXPECT_TRUE(with_id(bench.sync(), 0x183).empty());
  bench.nmt(0x01);
  const auto tpdo = with_id(bench.sync(), 0x183);
  ASSERT_EQ(tpdo.size(), 1u);
  EXPECT_EQ(tpdo[0].length, 6) << "statusword + position actual, the default mapping";
  EXPECT_EQ(le_u16(tpdo[0], 0) & 0x4F, 0x40) << "switch on disabled";
}

TEST(EmulatedDrive, PdoRemappingFollowsCiA301) {
  DriveBench bench;
  bench.power_on();
  // TPDO1 is valid: its mapping cannot change.
  EXPECT_EQ(bench.write(0x1A00, 0, 0, 1), 0x08000022u);
  // 1. Invalidate the PDO.
  EXPECT_EQ(bench.write(0x1800, 1, 0xC0000183u, 4), 0u);
  // Entries cannot change while sub 0 is not 0.
  EXPECT_EQ(bench.write(0x1A00, 1, 0x60410010u, 4), 0x08000022u);
  // 2. Disable the mapping.
  EXPECT_EQ(bench.write(0x1A00, 0, 0, 1), 0u);
  // 3. Write the entries; wrong ones are refused with the code CiA 301 names.
  EXPECT_EQ(bench.write(0x1A00, 1, 0x60410010u, 4), 0u);
  EXPECT_EQ(bench.write(0x1A00, 2, 0x606C0020u, 4), 0u);
  EXPECT_EQ(bench.write(0x1A00, 3, 0x60640020u, 4), 0u);
  EXPECT_EQ(bench.write(0x1A00, 4, 0x60640010u, 4), 0x06040041u) << "wrong length";
  EXPECT_EQ(bench.write(0x1A00, 4, 0x10080008u, 4), 0x06040041u) << "not mappable";
  EXPECT_EQ(bench.write(0x1A00, 4, 0x12340020u, 4), 0x06020000u) << "no such object";
  EXPECT_EQ(bench.write(0x1601, 1, 0x60410010u, 4), 0x06040041u) << "read-only into an RPDO";
  // 4. Enable the mapping: 80 bits do not fit a classic frame.
  EXPECT_EQ(bench.write(0x1A00, 0, 3, 1), 0x06040042u);
  EXPECT_EQ(bench.write(0x1A00, 3, 0x60770010u, 4), 0u);
  EXPECT_EQ(bench.write(0x1A00, 0, 3, 1), 0u);
  // 5. Validate the PDO; its COB-ID cannot change while it is valid.
  EXPECT_EQ(bench.write(0x1800, 1, 0x40000183u, 4), 0u);
  EXPECT_EQ(bench.write(0x1800, 1, 0x40000193u, 4), 0x06090030u);
  EXPECT_EQ(bench.write(0x1800, 2, 252, 1), 0x06090030u) << "RTR-only TPDOs are not supported";

  bench.nmt(0x01);
  const auto tpdo = with_id(bench.sync(), 0x183);
  ASSERT_EQ(tpdo.size(), 1u);
  EXPECT_EQ(tpdo[0].length, 8);
  EXPECT_EQ(le_u16(tpdo[0], 0), bench.upload(0x6041, 0).value);
  EXPECT_EQ(bench.upload(0x1A00, 0).value, 3u);
  EXPECT_EQ(bench.upload(0x1A00, 2).value, 0x606C0020u);
}

TEST(EmulatedDrive, FourPdosEachWayOnThePredefinedConnectionSet) {
  DriveBench bench;  // Node 3.
  bench.power_on();
  // CiA 301's predefined connection set: RPDO n at 0x100 (n + 1) + node, TPDO n at
  // 0x100 n + 0x80 + node; PDOs 2..4 delivered invalid (bit 31).
  for (std::uint16_t n = 2; n <= 4; ++n) {
    SCOPED_TRACE(n);
    EXPECT_EQ(bench.upload(static_cast<std::uint16_t>(0x1400 + n - 1), 1).value,
              0x8000'0000u | (0x100u * (n + 1u) + 3u));
    EXPECT_EQ(bench.upload(static_cast<std::uint16_t>(0x1800 + n - 1), 1).value & 0x8000'07FFu,
              0x8000'0000u | (0x100u * n + 0x80u + 3u));
  }
  EXPECT_EQ(bench.upload(0x1A03, 0).value, 0u) << "empty";
  // A standard master disables PDOs 2..4 (bit 31 set), then maps what it uses.
  for (std::uint16_t n = 2; n <= 4; ++n) {
    EXPECT_EQ(bench.write(static_cast<std::uint16_t>(0x1400 + n - 1), 1,
                          0x8000'0000u | (0x100u * (n + 1u) + 3u), 4),
              0u);
    EXPECT_EQ(bench.write(static_cast<std::uint16_t>(0x1800 + n - 1), 1,
                          0xC000'0000u | (0x100u * n + 0x80u + 3u), 4),
              0u);
  }
  // Capacity: 8 entries per PDO.
  EXPECT_EQ(bench.write(0x1A03, 0, 9, 1), 0x06090031u) << "value too high";
  // TPDO3 carries the statusword, RPDO4 (event-driven) the controlword.
  EXPECT_EQ(bench.write(0x1A02, 1, 0x60410010u, 4), 0u);
  EXPECT_EQ(bench.write(0x1A02, 0, 1, 1), 0u);
  EXPECT_EQ(bench.write(0x1802, 1, 0x40000383u, 4), 0u);
  EXPECT_EQ(bench.write(0x1603, 1, 0x60400010u, 4), 0u);
  EXPECT_EQ(bench.write(0x1603, 0, 1, 1), 0u);
  EXPECT_EQ(bench.write(0x1403, 2, 255, 1), 0u);
  EXPECT_EQ(bench.write(0x1403, 1, 0x00000503u, 4), 0u);
  bench.nmt(0x01);
  bench.exchange({frame(0x503, {0x06, 0x00})});  // Shutdown: transition 2.
  EXPECT_EQ(bench.drive().drive_state(), hal::DriveState::kReadyToSwitchOn);
  const auto frames = bench.sync();
  const auto tpdo3 = with_id(frames, 0x383);
  ASSERT_EQ(tpdo3.size(), 1u);
  EXPECT_EQ(tpdo3[0].length, 2);
  EXPECT_EQ(le_u16(tpdo3[0], 0) & 0x6F, 0x21) << "ready to switch on";
  EXPECT_TRUE(with_id(frames, 0x283).empty()) << "TPDO2 disabled";
  EXPECT_TRUE(with_id(frames, 0x483).empty()) << "TPDO4 disabled";
}

TEST(EmulatedDrive, TransmissionTypeSendsEveryNthSync) {
  DriveBench bench;
  bench.power_on();
  EXPECT_EQ(bench.write(0x1800, 2, 3, 1), 0u);
  bench.nmt(0x01);
  int sent = 0;
  for (int k = 0; k < 9; ++k) sent += static_cast<int>(with_id(bench.sync(), 0x183).size());
  EXPECT_EQ(sent, 3);
}

/// Sends RPDO1 (controlword, target position) and SYNC one millisecond after the last cycle;
/// returns the drive's TPDO1.
hal::CanFrame cycle(DriveBench& bench, std::uint16_t controlword, std::int32_t target_counts) {
  const auto t = static_cast<std::uint32_t>(target_counts);
  bench.clock().advance_to_ns(bench.now_ns() + kMs);
  const auto frames = bench.exchange(
      {frame(0x203,
             {static_cast<std::uint8_t>(controlword), static_cast<std::uint8_t>(controlword >> 8),
              static_cast<std::uint8_t>(t), static_cast<std::uint8_t>(t >> 8),
              static_cast<std::uint8_t>(t >> 16), static_cast<std::uint8_t>(t >> 24)}),
       frame(0x080, {})});
  const auto tpdo = with_id(frames, 0x183);
  EXPECT_EQ(tpdo.size(), 1u);
  return tpdo.empty() ? hal::CanFrame{} : tpdo[0];
}

hal::DriveState state_of(const hal::CanFrame& tpdo) {
  return canopen::cia402::drive_state_of(le_u16(tpdo, 0));
}

TEST(EmulatedDrive, CspFollowsTargetsLikeTheServoModelAlone) {
  const EmulatedDriveConfig config = pan_drive();
  DriveBench bench(config);
  const auto units = canopen::cia402::Units::from(config.gear_ratio, config.encoder_counts_per_rev);
  // The truth: the sim's servo model driven by hand with the same seed, one step per ms, the
  // targets taking effect at the SYNC after they were sent.
  sim::ServoModel model(config.servo, config.seed, config.initial_position_rad);
  const auto model_step = [&model] {
    model.step();
    model.observe(model.output_position_rad());
  };
  model.hold_at(config.initial_position_rad);

  bench.power_on();
  bench.nmt(0x01);
  const std::int32_t start_counts = units.to_counts(config.initial_position_rad);
  // Shutdown, switch on, enable: one state per SYNC.
  EXPECT_EQ(state_of(cycle(bench, 0x06, start_counts)), hal::DriveState::kSwitchOnDisabled);
  model_step();
  EXPECT_EQ(state_of(cycle(bench, 0x07, start_counts)), hal::DriveState::kReadyToSwitchOn);
  model_step();
  EXPECT_EQ(state_of(cycle(bench, 0x0F, start_counts)), hal::DriveState::kSwitchedOn);
  model_step();
  model.hold_at(model.output_position_rad());  // Enabled at the measured position.
  (void)model.command({hal::CommandMode::kPosition, units.to_rad(start_counts), 0.0, 0.0});

  double max_error_rad = 0.0;
  std::int32_t last_counts = 0;
  for (int k = 1; k <= 800; ++k) {
    const double t_s = k * 0.001;
    const double target_rad = config.initial_position_rad + 0.6 * std::sin(2.0 * t_s);
    const std::int32_t target_counts = units.to_counts(target_rad);
    const hal::CanFrame tpdo = cycle(bench, 0x0F, target_counts);
    model_step();
    ASSERT_EQ(state_of(tpdo), hal::DriveState::kOperationEnabled) << "cycle " << k;
    const std::int32_t expected = units.to_counts(model.encoder_position_rad());
    ASSERT_EQ(le_i32(tpdo, 2), expected) << "cycle " << k;
    (void)model.command({hal::CommandMode::kPosition, units.to_rad(target_counts), 0.0, 0.0});
    last_counts = le_i32(tpdo, 2);
    max_error_rad = std::max(max_error_rad, std::abs(units.to_rad(last_counts) - target_rad));
  }
  // It really moved, and followed: sin(1.6) * 0.6 away from the start, within a few mrad.
  EXPECT_NEAR(units.to_rad(last_counts) - config.initial_position_rad, 0.6 * std::sin(1.6), 0.02);
  EXPECT_LT(max_error_rad, 0.03);
}

TEST(EmulatedDrive, OldTargetIsNotExecutedOnEnable) {
  DriveBench bench;
  bench.power_on();
  bench.nmt(0x01);
  const auto units = bench.drive().units();
  const std::int32_t far = units.to_counts(-1.0);
  cycle(bench, 0x06, far);
  cycle(bench, 0x07, far);
  // Enable via SDO: the target written before stays unexecuted until a new one arrives.
  EXPECT_EQ(bench.write(0x6040, 0, 0x0F, 2), 0u);
  for (int k = 0; k < 50; ++k) {
    bench.clock().advance_to_ns(bench.now_ns() + kMs);
    bench.sync();
  }
  EXPECT_NEAR(bench.drive().servo().output_position_rad(), 0.25, 1e-9);
  EXPECT_EQ(bench.drive().drive_state(), hal::DriveState::kOperationEnabled);
}

TEST(EmulatedDrive, QuickStopBrakesAndHolds) {
  DriveBench bench;
  bench.power_on();
  bench.nmt(0x01);
  const auto units = bench.drive().units();
  cycle(bench, 0x06, 0);
  cycle(bench, 0x07, 0);
  cycle(bench, 0x0F, units.to_counts(0.25));
  for (int k = 0; k < 100; ++k) cycle(bench, 0x0F, units.to_counts(2.0));
  EXPECT_GT(std::abs(bench.drive().servo().state().profile_velocity_rad_s), 1.0);
  cycle(bench, 0x02, units.to_counts(2.0));  // Quick stop.
  hal::CanFrame tpdo;
  for (int k = 0; k < 200; ++k) tpdo = cycle(bench, 0x02, units.to_counts(2.0));
  EXPECT_EQ(state_of(tpdo), hal::DriveState::kQuickStopActive);
  EXPECT_TRUE(bench.drive().servo().at_rest());
  EXPECT_NE(le_u16(tpdo, 0) & canopen::cia402::kStatusTargetReached, 0) << "halted";
  EXPECT_LT(bench.drive().servo().output_position_rad(), 1.9) << "stopped short of the target";
}

TEST(EmulatedDrive, CsvMovesAtTheTargetVelocity) {
  EmulatedDriveConfig config = pan_drive();
  config.mode = hal::CommandMode::kVelocity;
  config.servo.motion_noise_std_rad = 0.0;
  DriveBench bench(config);
  bench.power_on();
  EXPECT_EQ(bench.upload(0x6061, 0).value, 9u);
  EXPECT_EQ(bench.upload(0x1600, 2).value, 0x60FF0020u) << "RPDO1 carries the target velocity";
  bench.nmt(0x01);
  const auto units = bench.drive().units();
  cycle(bench, 0x06, 0);
  cycle(bench, 0x07, 0);
  cycle(bench, 0x0F, 0);
  for (int k = 0; k < 500; ++k) cycle(bench, 0x0F, units.to_counts(1.0));  // 1 rad/s.
  // The target is whole counts/s: within one count of 1 rad/s.
  EXPECT_NEAR(bench.drive().servo().output_velocity_rad_s(), 1.0, 1.0 / units.counts_per_rad);
}

TEST(EmulatedDrive, ShortRpdoIsNotProcessedAndSaysSoByEmcy) {
  DriveBench bench;
  bench.power_on();
  bench.nmt(0x01);
  const auto frames = bench.exchange({frame(0x203, {0x06, 0x00, 0x01})});
  const auto emcy = with_id(frames, 0x083);
  ASSERT_EQ(emcy.size(), 1u);
  EXPECT_EQ(le_u16(emcy[0], 0), 0x8210);
  bench.sync();
  EXPECT_EQ(bench.drive().drive_state(), hal::DriveState::kSwitchOnDisabled);
}

// --- faults -----------------------------------------------------------------------------------

TEST(EmulatedDriveFaults, EmergencyLatchesAFaultUntilReset) {
  DriveBench bench;
  FaultInjection fault;
  fault.kind = FaultKind::kEmergency;
  fault.emcy_code = 0x7300;
  fault.at_s = 0.5;
  ASSERT_TRUE(bench.drive().schedule(fault));
  bench.power_on();
  EXPECT_EQ(bench.drive().next_event_ns(), 100 * kMs);
  EXPECT_TRUE(with_id(bench.advance_to_ns(499 * kMs), 0x083).empty());
  const auto emcy = with_id(bench.advance_to_ns(500 * kMs), 0x083);
  ASSERT_EQ(emcy.size(), 1u);
  EXPECT_EQ(emcy[0].length, 8);
  EXPECT_EQ(le_u16(emcy[0], 0), 0x7300);
  EXPECT_EQ(emcy[0].data[2] & 0x01, 0x01) << "generic error bit";
  bench.advance_to_ns(501 * kMs);
  EXPECT_EQ(bench.upload(0x603F, 0).value, 0x7300u);
  EXPECT_EQ(
      canopen::cia402::drive_state_of(static_cast<std::uint16_t>(bench.upload(0x6041, 0).value)),
      hal::DriveState::kFault);
  // Fault reset: bit 7's rising edge.
  EXPECT_EQ(bench.write(0x6040, 0, 0x00, 2), 0u);
  const auto reset = bench.download(0x6040, 0, 0x80, 2);
  EXPECT_EQ(reset.command, 0x60);
  const auto cleared = with_id(bench.log(), 0x083);
  ASSERT_EQ(cleared.size(), 2u);
  EXPECT_EQ(le_u16(cleared[1], 0), 0x0000);
  EXPECT_EQ(cleared[1].data[2], 0x00);
  EXPECT_EQ(bench.drive().drive_state(), hal::DriveState::kSwitchOnDisabled);
}

TEST(EmulatedDriveFaults, FollowingErrorFaultsTheDrive) {
  EmulatedDriveConfig config = pan_drive();
  config.following_error_window_rad = 0.01;
  DriveBench bench(config);
  bench.power_on();
  bench.nmt(0x01);
  const auto units = bench.drive().units();
  cycle(bench, 0x06, 0);
  cycle(bench, 0x07, 0);
  cycle(bench, 0x0F, units.to_counts(0.25));
  for (int k = 0; k < 5; ++k) cycle(bench, 0x0F, units.to_counts(0.25));
  EXPECT_EQ(bench.drive().drive_state(), hal::DriveState::kOperationEnabled);
  cycle(bench, 0x0F, units.to_counts(1.0));  // A jump far beyond the window.
  const hal::CanFrame tpdo = cycle(bench, 0x0F, units.to_counts(1.0));
  const auto emcy = with_id(bench.log(), 0x083);
  ASSERT_EQ(emcy.size(), 1u);
  EXPECT_EQ(le_u16(emcy[0], 0), 0x8611);
  EXPECT_TRUE(hal::is_faulted(state_of(tpdo)));
  EXPECT_NE(le_u16(tpdo, 0) & canopen::cia402::kStatusFollowingError, 0);
}

TEST(EmulatedDriveFaults, InjectedFollowingError) {
  DriveBench bench;
  ASSERT_TRUE(bench.drive().schedule(parse_fault("following-error,at_s=0.01")));
  bench.power_on();
  bench.nmt(0x01);
  const auto tpdo = with_id(bench.advance_to_ns(20 * kMs), 0x083);
  ASSERT_EQ(tpdo.size(), 1u);
  EXPECT_EQ(le_u16(tpdo[0], 0), 0x8611);
}

TEST(EmulatedDriveFaults, HeartbeatStops) {
  DriveBench bench;
  ASSERT_TRUE(bench.drive().schedule(parse_fault("heartbeat-stop,node=3,at_s=0.25")));
  bench.power_on();
  int beats = 0;
  for (int t = 10; t <= 600; t += 10)
    beats += static_cast<int>(with_id(bench.advance_to_ns(t * kMs), 0x703).size());
  EXPECT_EQ(beats, 2) << "at 100 and 200 ms, then silence";
  EXPECT_EQ(bench.upload(0x1000, 0).value, 0x00020192u) << "the rest of the node still answers";
}

TEST(EmulatedDriveFaults, FaultsForOtherNodesAreNotTaken) {
  DriveBench bench;
  EXPECT_FALSE(bench.drive().schedule(parse_fault("heartbeat-stop,node=4")));
}

TEST(EmulatedDriveFaults, DroppedTpdos) {
  DriveBench bench;
  ASSERT_TRUE(bench.drive().schedule(parse_fault("drop-tpdo,count=2")));
  bench.power_on();
  bench.nmt(0x01);
  EXPECT_TRUE(with_id(bench.sync(), 0x183).empty());
  EXPECT_TRUE(with_id(bench.sync(), 0x183).empty());
  EXPECT_EQ(with_id(bench.sync(), 0x183).size(), 1u);
  EXPECT_EQ(bench.drive().counters().tpdos_dropped, 2u);
}

TEST(EmulatedDriveFaults, LateTpdos) {
  DriveBench bench;
  ASSERT_TRUE(bench.drive().schedule(parse_fault("late-tpdo,count=1,delay_ms=5")));
  bench.power_on();
  bench.nmt(0x01);
  bench.advance_to_ns(10 * kMs);
  EXPECT_TRUE(with_id(bench.sync(), 0x183).empty());
  EXPECT_EQ(bench.drive().next_event_ns(), 15 * kMs);
  EXPECT_TRUE(with_id(bench.advance_to_ns(14 * kMs), 0x183).empty());
  EXPECT_EQ(with_id(bench.advance_to_ns(15 * kMs), 0x183).size(), 1u);
  EXPECT_EQ(with_id(bench.sync(), 0x183).size(), 1u) << "on time again";
}

TEST(EmulatedDriveFaults, SdoAbortOnAnObject) {
  DriveBench bench;
  ASSERT_TRUE(bench.drive().schedule(parse_fault("sdo-abort,object=0x6065:0,code=0x06060000")));
  bench.power_on();
  EXPECT_EQ(bench.upload(0x6065, 0).value, 0x06060000u);
  EXPECT_TRUE(bench.upload(0x6065, 0).abort());
  EXPECT_EQ(bench.write(0x6065, 0, 5, 4), 0x06060000u);
  EXPECT_FALSE(bench.upload(0x6064, 0).abort());
}

TEST(EmulatedDriveFaults, ErrorFrameBurstIsReportedAsErrorPassive) {
  DriveBench bench;
  ASSERT_TRUE(bench.drive().schedule(parse_fault("error-frames,count=3")));
  bench.power_on();
  bench.nmt(0x01);
  auto emcy = with_id(bench.log(), 0x083);
  ASSERT_EQ(emcy.size(), 1u);
  EXPECT_EQ(le_u16(emcy[0], 0), 0x8120);
  EXPECT_EQ(emcy[0].data[2], 0x11) << "generic + communication";
  const auto tpdo = with_id(bench.sync(), 0x183);
  EXPECT_NE(le_u16(tpdo[0], 0) & canopen::cia402::kStatusWarning, 0);
  bench.sync();
  bench.sync();
  emcy = with_id(bench.log(), 0x083);
  ASSERT_EQ(emcy.size(), 2u);
  EXPECT_EQ(le_u16(emcy[1], 0), 0x0000);
  EXPECT_EQ(bench.drive().drive_state(), hal::DriveState::kSwitchOnDisabled) << "no drive fault";
}

/// What parse_fault says of `spec`: its error, or "accepted".
std::string fault_message(std::string_view spec) {
  try {
    (void)parse_fault(spec);
  } catch (const std::invalid_argument& error) {
    return std::string(error.what());
  }
  return std::string("accepted");
}

TEST(FaultSpec, ParsesAndRefusesWithClearMessages) {
  const FaultInjection emcy = parse_fault("emcy,node=2,at_s=1.5,code=0x7300,fault=no");
  EXPECT_EQ(emcy.kind, FaultKind::kEmergency);
  EXPECT_EQ(emcy.node_id, 2);
  EXPECT_DOUBLE_EQ(emcy.at_s, 1.5);
  EXPECT_EQ(emcy.emcy_code, 0x7300);
  EXPECT_FALSE(emcy.latch_fault);
  const FaultInjection late = parse_fault("late-tpdo,count=4,delay_ms=3");
  EXPECT_EQ(late.count, 4);
  EXPECT_DOUBLE_EQ(late.delay_s, 0.003);
  const auto message = fault_message;
  EXPECT_NE(message("smoke").find("unknown kind 'smoke'"), std::string::npos);
  EXPECT_NE(message("emcy,node=200").find("node: expected 1 to 127"), std::string::npos);
  EXPECT_NE(message("emcy,at_s=soon").find("at_s: expected a number"), std::string::npos);
  EXPECT_NE(message("heartbeat-stop,code=1").find("does not apply"), std::string::npos);
  EXPECT_NE(message("sdo-abort,node=1").find("needs object"), std::string::npos);
  EXPECT_NE(message("emcy,node").find("expected key=value"), std::string::npos);
}

TEST(FaultSpec, AKeyGivenTwiceOrTwoTimesAreRefusedNotTheLastWinning) {
  const auto message = fault_message;
  EXPECT_NE(message("emcy,node=1,node=2").find("key 'node' given twice"), std::string::npos);
  EXPECT_NE(message("emcy,at_s=1,after_enable_s=2").find("give one time"), std::string::npos);
  EXPECT_NE(message("emcy,at_s=1,at_s=2").find("give one time"), std::string::npos);
  // What the message repeats is escaped: a NUL no longer cuts it, an escape sequence is inert.
  const std::string nul = message(std::string_view("smo\0ke,node=1", 14));
  EXPECT_NE(nul.find("unknown kind 'smo\\x00ke'"), std::string::npos) << nul;
  EXPECT_NE(nul.find("expected one of"), std::string::npos) << nul;
  const std::string escape = message("emcy,node=\x1b[2J");
  EXPECT_EQ(escape.find('\x1b'), std::string::npos) << escape;
  EXPECT_NE(escape.find("\\x1b[2J"), std::string::npos) << escape;
}

TEST(EmulatedDrive, NoAllocationOnTheBusSide) {
  // Everything a cycle and configuration need, frames handed over directly (the bench's vectors
  // allocate; the drive must not).
  can::InProcessCanNetwork network;
  hal::CanBus& master = network.add_endpoint("master");
  hal::CanBus& drive_bus = network.add_endpoint("drive");
  EmulatedDrive drive(pan_drive(), drive_bus);
  ASSERT_TRUE(drive.schedule(parse_fault("late-tpdo,count=3,delay_ms=1")));
  const auto before = runtime::thread_allocation_count();
  drive.power_on(0);
  std::int64_t t = 0;
  const auto feed = [&](const hal::CanFrame& f) {
    drive.handle(f, t);
    hal::CanFrame out;
    while (master.receive(out) == hal::Status::kOk) {
    }
  };
  feed(frame(0x000, {0x01, 3}));
  feed(frame(0x603, {0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0}));  // Segmented upload.
  feed(frame(0x603, {0x60, 0, 0, 0, 0, 0, 0, 0}));
  feed(frame(0x603, {0x23, 0x65, 0x60, 0x00, 1, 2, 3, 4}));
  for (int k = 0; k < 1000; ++k) {
    t += kMs;
    feed(frame(0x203, {0x0F, 0x00, 0x10, 0x20, 0x00, 0x00}));
    feed(frame(0x080, {}));
    drive.poll(t);
  }
  EXPECT_EQ(runtime::thread_allocation_count() - before, 0u);
  EXPECT_GT(drive.counters().tpdos_sent, 990u);
}

}  // namespace
}  // namespace cambio::virtual_rig::test
