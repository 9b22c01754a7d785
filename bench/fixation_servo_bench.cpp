// Cost of one call of the gaze loop's control law (ViSP's vpServo behind FixationServo) on the
// shipped rig, a 35° gaze shift at 1 m: the figure a unit test must not assert (a sanitizer build
// or a busy machine makes any bound flaky), kept here beside the 5 ms control period it serves.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <span>
#include <vector>

#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/control/fixation_servo.hpp"

namespace cambio {
namespace {

void BM_FixationServoVelocity(benchmark::State& state) {
  const hal::HardwareInfo hardware = config::hardware_description(
      config::load_rig(config::find_shipped_config("rigs/cambio.yaml")));
  control::Kinematics kinematics(hardware);
  control::FixationParams params;
  params.dominant_eye = hal::Eye::kLeft;
  params.gain_per_s = 5.0;
  params.neck_rule_rad = 30.0 * std::numbers::pi / 180.0;
  params.default_depth_m = 1.0;
  control::FixationServo servo(hardware, params);

  const std::vector<double> q(kinematics.joint_count(), 0.0);
  const double azimuth_rad = 35.0 * std::numbers::pi / 180.0;
  const Eigen::Vector4d target(std::cos(azimuth_rad), std::sin(azimuth_rad), 1.4, 1.0);
  std::vector<double> qdot(q.size());
  for (auto _ : state) {
    if (servo.velocity(std::span<const double>(q), target, 0.05, qdot) != hal::Status::kOk) {
      state.SkipWithError("velocity() refused the shipped rig's 35 degree shift");
      break;
    }
    benchmark::DoNotOptimize(qdot.data());
  }
}
BENCHMARK(BM_FixationServoVelocity)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace cambio
