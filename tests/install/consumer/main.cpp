// Uses the installed HAL and config loader the way a user's driver or tool would.
#include <cstdio>

#include "cambio/config/rig_loader.hpp"
#include "cambio/hal/image.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/hal/seqlock_channel.hpp"

int main() {
  cambio::hal::Image image(4, 3, cambio::hal::PixelFormat::kRgb8);
  cambio::hal::ManualClock clock;
  clock.sleep_until_ns(42);
  cambio::hal::SeqlockChannel<double> channel;
  channel.write(1.5);
  double value = 0.0;
  channel.read(value);
  const auto rig = cambio::config::load_rig_from_string(
      "rig: {name: tiny}\n"
      "joints:\n"
      "  pan: {group: g, parent: base, axis: [0, 0, 1], min_position_deg: -90,\n"
      "        max_position_deg: 90, max_velocity_rad_s: 1, max_acceleration_rad_s2: 10}\n"
      "groups:\n"
      "  g: {backend: sim, joints: [pan]}\n",
      "consumer.yaml");
  const bool ok = image.pixels.size() == 36 && clock.now_ns() == 42 && value == 1.5 &&
                  rig.joints.size() == 1 && rig.joints[0].max_position_rad > 1.5707 &&
                  rig.joints[0].max_position_rad < 1.5708;
  std::printf("consumer: %s\n", ok ? "ok" : "MISMATCH");
  return ok ? 0 : 1;
}
