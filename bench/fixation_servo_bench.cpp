// Cost of the gaze and arm loops' control laws: one FixationServo::velocity() on the shipped rig,
// a 35° gaze shift at 1 m, and each law alone, the allocation-free Eigen law the loops run beside
// ViSP's own vpServo it is held to (tests/control/visual_servo_law_visp_test.cpp). Figures a unit
// test must not assert (a sanitizer build or a busy machine makes any bound flaky), kept here
// beside the 5 ms control period they serve.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <span>
#include <vector>

#include "arm_reach_law.hpp"
#include "arm_reach_servo_visp.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/control/fixation_servo.hpp"
#include "fixation_law.hpp"
#include "fixation_servo_visp.hpp"

namespace cambio {
namespace {

// The shipped rig's fixation servo, and the 35° gaze shift at 1 m it is timed on.
struct ShippedFixation {
  ShippedFixation()
      : hardware(config::hardware_description(
            config::load_rig(config::find_shipped_config("rigs/cambio.yaml")))),
        servo(hardware, params()),
        q(static_cast<std::size_t>(control::Kinematics(hardware).joint_count()), 0.0),
        target(std::cos(kAzimuthRad), std::sin(kAzimuthRad), 1.4, 1.0) {}
  static control::FixationParams params() {
    control::FixationParams p;
    p.dominant_eye = hal::Eye::kLeft;
    p.gain_per_s = 5.0;
    p.neck_rule_rad = 30.0 * std::numbers::pi / 180.0;
    p.default_depth_m = 1.0;
    return p;
  }
  static constexpr double kAzimuthRad = 35.0 * std::numbers::pi / 180.0;
  hal::HardwareInfo hardware;
  control::FixationServo servo;
  std::vector<double> q;
  Eigen::Vector4d target;
};

void BM_FixationServoVelocity(benchmark::State& state) {
  ShippedFixation shipped;
  std::vector<double> qdot(shipped.q.size());
  for (auto _ : state) {
    if (shipped.servo.velocity(std::span<const double>(shipped.q), shipped.target, 0.05, qdot) !=
        hal::Status::kOk) {
      state.SkipWithError("velocity() refused the shipped rig's 35 degree shift");
      break;
    }
    benchmark::DoNotOptimize(qdot.data());
  }
}
BENCHMARK(BM_FixationServoVelocity)->Unit(benchmark::kMicrosecond);

// A saccade's end pose: the law iterated on the model until it stops (the gaze loop's update()
// runs it when a saccade starts).
void BM_FixationServoSolve(benchmark::State& state) {
  ShippedFixation shipped;
  std::vector<double> q_end(shipped.q.size());
  for (auto _ : state) {
    if (shipped.servo.solve(std::span<const double>(shipped.q), shipped.target, 0.05, q_end) !=
        hal::Status::kOk) {
      state.SkipWithError("solve() refused the shipped rig's 35 degree shift");
      break;
    }
    benchmark::DoNotOptimize(q_end.data());
  }
}
BENCHMARK(BM_FixationServoSolve)->Unit(benchmark::kMicrosecond);

// One fixation law: a point 0.3 left and 0.2 up in normalized coordinates at 1.5 m, a camera
// Jacobian with the neck's columns weighted down, the neck rule's secondary task.
template <class Law>
void BM_FixationLaw(benchmark::State& state) {
  Law law(5.0);
  Eigen::Matrix<double, 6, 4> eJe;
  eJe << 0.01, 0.0, 0.0, 0.0,  //
      0.0, -0.02, -0.1, 0.0,   //
      -0.01, 0.0, 0.0, 0.1,    //
      0.0, 0.1, 1.0, 0.0,      //
      -0.1, 0.0, 0.0, 1.0,     //
      0.0, 0.0, 0.0, 0.0;
  const Eigen::Vector4d u2(0.5, 0.0, 0.0, 0.0);
  Eigen::Vector4d u;
  for (auto _ : state) {
    if (!law.control_law(0.3, -0.2, 1.5, eJe, u2, u)) {
      state.SkipWithError("the fixation law refused its state");
      break;
    }
    benchmark::DoNotOptimize(u.data());
  }
}
BENCHMARK(BM_FixationLaw<control::detail::FixationLaw>)->Name("BM_FixationLaw/eigen");
BENCHMARK(BM_FixationLaw<control::detail::FixationServoVisp>)->Name("BM_FixationLaw/visp");

// One arm law: the fingertips 0.2 m from the aim, the posture's secondary task, two joints in
// the joint-limit avoidance's bands.
template <class Law>
void BM_ArmReachLaw(benchmark::State& state) {
  Law law(4.0);
  Eigen::Matrix<double, 3, 4> J_v;
  J_v << 0.0, -0.3, -0.2, -0.1,  //
      0.45, 0.0, 0.0, 0.0,       //
      0.0, 0.35, 0.15, 0.05;
  const Eigen::Vector3d e_W(0.15, -0.05, 0.12);
  const Eigen::Vector4d u2(0.1, -0.2, 0.05, 0.0);
  const Eigen::Vector4d q_min(-1.5, -0.5, 0.0, -1.6);
  const Eigen::Vector4d q_max(1.5, 2.5, 2.4, 1.6);
  const Eigen::Vector4d q(0.1, 2.4, 1.2, -1.5);
  Eigen::Vector4d qdot;
  for (auto _ : state) {
    if (!law.control_law(e_W, J_v, u2, q, q_min, q_max, qdot)) {
      state.SkipWithError("the arm law refused its state");
      break;
    }
    benchmark::DoNotOptimize(qdot.data());
  }
}
BENCHMARK(BM_ArmReachLaw<control::detail::ArmReachLaw>)->Name("BM_ArmReachLaw/eigen");
BENCHMARK(BM_ArmReachLaw<control::detail::ArmReachServoVisp>)->Name("BM_ArmReachLaw/visp");

}  // namespace
}  // namespace cambio
