#include "can_pdo_throughput.hpp"

#include <chrono>
#include <cstdint>

#include "cambio/canopen/pdo_codec.hpp"
#include "cambio/canopen/pdo_layout.hpp"
#include "cambio/canopen/protocol.hpp"

namespace cambio::app {

namespace {

using WallClock = std::chrono::steady_clock;

/// Where the PDO loop's result goes: the optimiser must assume someone reads it, so the loop is
/// not dead code.
volatile std::uint64_t pdo_checksum_sink = 0;

}  // namespace

double pdo_frames_per_s(long long frame_pairs) {
  const canopen::PdoLayout layout = canopen::pdo_layout(hal::CommandMode::kPosition, {});
  hal::CanFrame frame;
  canopen::DriveTargets targets;
  canopen::DriveFeedback feedback;
  std::uint64_t checksum = 0;
  const auto start = WallClock::now();
  for (long long i = 0; i < frame_pairs; ++i) {
    targets.controlword = static_cast<std::uint16_t>(0x000F ^ (i & 1));
    targets.target_position_counts = static_cast<std::int32_t>(i * 7);
    canopen::pack_pdo(
        layout.rpdos[0], 0x201,
        [&targets](canopen::ObjectAddress object) { return canopen::raw_target(targets, object); },
        frame);
    canopen::DriveTargets received;
    (void)canopen::unpack_pdo(
        layout.rpdos[0], frame,
        [&received](canopen::ObjectAddress object, std::uint32_t raw, std::size_t) {
          if (object == canopen::cia402::kControlword) {
            received.controlword = static_cast<std::uint16_t>(raw);
          } else {
            received.target_position_counts = static_cast<std::int32_t>(raw);
          }
        });
    feedback.statusword = received.controlword;
    feedback.position_counts = received.target_position_counts - 3;
    canopen::pack_pdo(
        layout.tpdos[0], 0x181,
        [&feedback](canopen::ObjectAddress object) -> std::uint32_t {
          if (object == canopen::cia402::kStatusword) return feedback.statusword;
          return static_cast<std::uint32_t>(feedback.position_counts);
        },
        frame);
    canopen::DriveFeedback decoded;
    (void)canopen::unpack_pdo(
        layout.tpdos[0], frame,
        [&decoded](canopen::ObjectAddress object, std::uint32_t raw, std::size_t bytes) {
          canopen::store_feedback(decoded, object, raw, bytes);
        });
    checksum += static_cast<std::uint32_t>(decoded.position_counts) + decoded.statusword;
  }
  const double elapsed_s = std::chrono::duration<double>(WallClock::now() - start).count();
  pdo_checksum_sink = checksum;
  return 2.0 * static_cast<double>(frame_pairs) / elapsed_s;
}

}  // namespace cambio::app
