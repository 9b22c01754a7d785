// The emulated drive's homing mode (6) driven with raw CiA 301/402 frames: the statusword's
// homing bits (CiA 402-2 Table 73) in order, the joint ending at the limit switch's edge or the
// index pulse (closed form from the start position, the switch and the pulse pitch), the home
// offset applied as CiA 402 defines it (zero = home + offset: the home position reads -offset),
// a homing error at the joint's limit, an unsupported method refused with an SDO abort.
#include <cmath>
#include <numbers>
#include <vector>

#include "drive_test_support.hpp"

namespace cambio::virtual_rig::test {
namespace {

constexpr std::int64_t kMs = 1'000'000;
// Statusword bits, as CiA 402-2 numbers them (not the project's constants).
constexpr std::uint32_t kTargetReached = 1u << 10;
constexpr std::uint32_t kAttained = 1u << 12;
constexpr std::uint32_t kHomingError = 1u << 13;
constexpr std::uint32_t kHomingBits = kTargetReached | kAttained | kHomingError;

struct HomingRun {
  std::vector<std::uint32_t> statuswords;  ///< Each change, from the start.
  double seconds = 0.0;                    ///< Until completed or error.
};

class HomingBench {
 public:
  explicit HomingBench(EmulatedDriveConfig config) : bench(config) {
    bench.power_on();
    counts_per_rad = 50.0 * 4096.0 / (2.0 * std::numbers::pi);
  }

  /// Writes the homing objects, selects mode 6 and enables (shutdown, switch on, enable).
  void prepare(int method, double switch_speed_rad_s, double zero_speed_rad_s,
               std::int32_t offset_counts) {
    EXPECT_EQ(bench.write(0x6098, 0, static_cast<std::uint8_t>(method), 1), 0u);
    EXPECT_EQ(bench.write(0x6099, 1, counts(switch_speed_rad_s), 4), 0u);
    EXPECT_EQ(bench.write(0x6099, 2, counts(zero_speed_rad_s), 4), 0u);
    EXPECT_EQ(bench.write(0x607C, 0, static_cast<std::uint32_t>(offset_counts), 4), 0u);
    EXPECT_EQ(bench.write(0x6060, 0, 6, 1), 0u);
    for (std::uint32_t controlword : {0x06u, 0x07u, 0x0Fu}) {
      EXPECT_EQ(bench.write(0x6040, 0, controlword, 2), 0u);
    }
    EXPECT_EQ(bench.upload(0x6041, 0).value & 0x6F, 0x27u) << "operation enabled";
    EXPECT_EQ(bench.upload(0x6041, 0).value & kHomingBits, kTargetReached)
        << "homing not started: bit 10 alone";
  }

  /// Raises bit 4 and polls the statusword every 5 ms until it is completed or in error.
  HomingRun run(double limit_s) {
    HomingRun run;
    EXPECT_EQ(bench.write(0x6040, 0, 0x1F, 2), 0u);
    const std::int64_t start_ns = bench.now_ns();
    while (bench.now_ns() - start_ns < static_cast<std::int64_t>(limit_s * 1e9)) {
      bench.advance_to_ns(bench.now_ns() + 5 * kMs);
      const std::uint32_t statusword = bench.upload(0x6041, 0).value;
      if (run.statuswords.empty() || run.statuswords.back() != statusword) {
        run.statuswords.push_back(statusword);
      }
      const std::uint32_t homing = statusword & kHomingBits;
      if (homing == (kAttained | kTargetReached) || (homing & kHomingError) != 0) break;
    }
    run.seconds = static_cast<double>(bench.now_ns() - start_ns) * 1e-9;
    return run;
  }

  std::int32_t position_counts() {
    return static_cast<std::int32_t>(bench.upload(0x6064, 0).value);
  }
  std::uint32_t counts(double rad) const {
    return static_cast<std::uint32_t>(std::lround(rad * counts_per_rad));
  }

  DriveBench bench;
  double counts_per_rad = 1.0;
};

EmulatedDriveConfig drive_with(std::optional<double> switch_rad, double index_rad = 0.0) {
  EmulatedDriveConfig config = pan_drive();
  config.home_switch_rad = switch_rad;
  config.index_pulse_rad = index_rad;
  return config;
}

/// The homing bits of each statusword, in order, with repeats of the same bits dropped.
std::vector<std::uint32_t> homing_bits(const std::vector<std::uint32_t>& statuswords) {
  std::vector<std::uint32_t> bits;
  for (std::uint32_t statusword : statuswords) {
    if (bits.empty() || bits.back() != (statusword & kHomingBits)) {
      bits.push_back(statusword & kHomingBits);
    }
  }
  return bits;
}

TEST(EmulatedDriveHoming, NegativeLimitSwitchEndsAtTheSwitchEdgeReadingMinusTheOffset) {
  const double switch_rad = -0.3;  // Start 0.25 (pan_drive): 0.55 rad to the switch.
  HomingBench h(drive_with(switch_rad));
  const std::int32_t offset_counts = 3000;
  h.prepare(17, 1.0, 0.05, offset_counts);
  const HomingRun run = h.run(5.0);
  // In progress (none of 10/12/13), attained while moving back (12), completed (12 + 10).
  EXPECT_EQ(homing_bits(run.statuswords),
            (std::vector<std::uint32_t>{0, kAttained, kAttained | kTargetReached}));
  // At least the way to the switch at the switch speed.
  EXPECT_GT(run.seconds, 0.55 / 1.0);
  EXPECT_LT(run.seconds, 1.5);
  // The joint stands on the edge (motion noise 0.2 mrad, encoder 65536 per turn).
  EXPECT_NEAR(h.bench.drive().servo().output_position_rad(), switch_rad, 1e-3);
  // Zero = home + offset: the home position reads -offset; here the joint reads its distance
  // from the edge, less the offset.
  const double expected_counts =
      (h.bench.drive().servo().encoder_position_rad() - switch_rad) * h.counts_per_rad -
      offset_counts;
  EXPECT_NEAR(h.position_counts(), expected_counts, 1.0);
  EXPECT_NEAR(h.position_counts(), -offset_counts, 1e-3 * h.counts_per_rad);
}

TEST(EmulatedDriveHoming, StartingOnThePositiveSwitchBacksOffItAtTheZeroSpeed) {
  const double switch_rad = 0.2;  // Start 0.25: already on the positive limit switch.
  HomingBench h(drive_with(switch_rad));
  h.prepare(18, 1.0, 0.05, 0);
  const HomingRun run = h.run(5.0);
  ASSERT_EQ(run.statuswords.back() & kHomingBits, kAttained | kTargetReached);
  // 0.05 rad off the switch at 0.05 rad/s: about a second, never at the switch speed.
  EXPECT_GT(run.seconds, 0.05 / 0.05);
  EXPECT_LT(run.seconds, 1.5);
  EXPECT_NEAR(h.bench.drive().servo().output_position_rad(), switch_rad, 1e-3);
  EXPECT_NEAR(h.position_counts(), 0.0, 1e-3 * h.counts_per_rad);
}

TEST(EmulatedDriveHoming, IndexPulseMethodsStopAtTheFirstPulseEachWay) {
  // Pulses every motor turn: 2 pi / 50 of the joint; one at 0.1 rad. From 0.25:
  //   33 (negative): 0.1 + floor((0.25 - 0.1) / p) p = 0.1 + p
  //   34 (positive): 0.1 + (floor((0.25 - 0.1) / p) + 1) p = 0.1 + 2 p
  const double pitch_rad = 2.0 * std::numbers::pi / 50.0;
  const double start_rad = 0.25;
  for (const int method : {33, 34}) {
    SCOPED_TRACE(method);
    HomingBench h(drive_with(std::nullopt, 0.1));
    const std::int32_t offset_counts = -500;
    h.prepare(method, 1.0, 0.2, offset_counts);
    const HomingRun run = h.run(5.0);
    ASSERT_EQ(run.statuswords.back() & kHomingBits, kAttained | kTargetReached);
    const double k = std::floor((start_rad - 0.1) / pitch_rad) + (method == 34 ? 1.0 : 0.0);
    const double home_rad = 0.1 + k * pitch_rad;
    EXPECT_NEAR(h.bench.drive().servo().output_position_rad(), home_rad, 1e-3);
    EXPECT_NEAR(h.position_counts(), -offset_counts, 1e-3 * h.counts_per_rad);
  }
}

TEST(EmulatedDriveHoming, NoSwitchBeforeTheJointLimitIsAHomingError) {
  HomingBench h(drive_with(std::nullopt));
  h.prepare(18, 3.0, 0.05, 0);
  const HomingRun run = h.run(5.0);
  const std::uint32_t last = run.statuswords.back();
  EXPECT_NE(last & kHomingError, 0u);
  EXPECT_EQ(last & kAttained, 0u);
  // At the limit (2.9 rad): stood still, so the error reads with bit 10 once at rest.
  h.bench.advance_to_ns(h.bench.now_ns() + 200 * kMs);
  EXPECT_EQ(h.bench.upload(0x6041, 0).value & kHomingBits, kHomingError | kTargetReached);
  EXPECT_NEAR(h.bench.drive().servo().output_position_rad(), 2.9, 1e-3);
}

TEST(EmulatedDriveHoming, ClearingBit4InterruptsAndCspAfterHomingDoesNotJump) {
  HomingBench h(drive_with(-0.3));
  h.prepare(17, 1.0, 0.05, 0);
  EXPECT_EQ(h.bench.write(0x6040, 0, 0x1F, 2), 0u);
  h.bench.advance_to_ns(h.bench.now_ns() + 100 * kMs);
  EXPECT_EQ(h.bench.upload(0x6041, 0).value & kHomingBits, 0u) << "in progress";
  EXPECT_EQ(h.bench.write(0x6040, 0, 0x0F, 2), 0u);
  EXPECT_EQ(h.bench.upload(0x6041, 0).value & kHomingBits, kTargetReached) << "interrupted";
}

TEST(EmulatedDriveHoming, UnsupportedMethodsAreRefusedWithAnSdoAbort) {
  DriveBench bench(pan_drive());
  bench.power_on();
  for (const int method : {1, 2, 19, 35 + 1, -1}) {
    SCOPED_TRACE(method);
    EXPECT_EQ(bench.write(0x6098, 0, static_cast<std::uint8_t>(method), 1), 0x0609'0030u)
        << "value range of parameter exceeded";
  }
  EXPECT_EQ(bench.upload(0x6098, 0).value, 0u) << "unchanged";
  EXPECT_EQ(bench.write(0x6098, 0, 17, 1), 0u);
  EXPECT_EQ(bench.upload(0x6502, 0).value & (1u << 5), 1u << 5) << "homing mode supported";
}

}  // namespace
}  // namespace cambio::virtual_rig::test
