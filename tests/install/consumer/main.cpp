// Uses the installed libraries the way a user's driver or tool would: the HAL's types, the
// config loader, the lockstep executor, the perception kernels, the sim backend's factory and the
// gaze's fixation servo (ViSP's law computed by cambio::control itself: this project never names
// ViSP).
#include <cstdio>
#include <vector>

#include "cambio/config/experiment_config.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/control/fixation_servo.hpp"
#include "cambio/hal/backend_factory.hpp"
#include "cambio/hal/image.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/perception/gaussian_kernels.hpp"
#include "cambio/runtime/lockstep_executor.hpp"
#include "cambio/sim/sim_backend.hpp"

namespace {
class CountingLoop final : public cambio::hal::Loop {
 public:
  const std::string& name() const override { return name_; }
  cambio::hal::Status update(const cambio::hal::LoopTick&) noexcept override {
    ++cycles;
    return cambio::hal::Status::kOk;
  }
  int cycles = 0;

 private:
  std::string name_ = "count";
};
}  // namespace

int main(int argc, char** argv) {
  cambio::hal::Image image(4, 3, cambio::hal::PixelFormat::kRgb8);
  cambio::hal::SeqlockChannel<double> channel;
  channel.write(1.5);
  double value = 0.0;
  channel.read(value);

  // The experiment shipped in the prefix, with the rig and perception files it names.
  const auto experiment = cambio::config::load_experiment(argv[argc - 1]);

  CountingLoop loop;
  cambio::runtime::LockstepExecutor executor;
  executor.add_loop({&loop, cambio::runtime::LoopSchedule{100.0}});
  executor.configure();
  executor.run_until_ns(1'000'000'000);

  cambio::hal::BackendFactory factory;
  cambio::sim::register_sim_backend(factory, experiment.rig, cambio::config::SceneConfig{});
  const cambio::hal::HardwareInfo hardware = cambio::config::hardware_description(experiment.rig);

  cambio::control::FixationParams fixation;
  fixation.gain_per_s = 4.0;
  fixation.neck_rule_rad = 0.5236;
  fixation.default_depth_m = 1.0;
  cambio::control::FixationServo servo(hardware, fixation);
  std::vector<double> q(hardware.joints.size(), 0.0);
  std::vector<double> qdot(hardware.joints.size(), 0.0);
  const bool servo_ok = servo.velocity(q, Eigen::Vector4d(1.0, 0.3, 1.4, 1.0), 0.0, qdot) ==
                            cambio::hal::Status::kOk &&
                        qdot[static_cast<std::size_t>(servo.head().eye_pan[0])] > 0.0;

  const bool ok = servo_ok && image.pixels.size() == 36 && value == 1.5 &&
                  experiment.rig.joints.size() == 15 && hardware.joints.size() == 15 &&
                  hardware.stereo.has_value() && !experiment.perception_path.empty() &&
                  loop.cycles == 100 && factory.has("sim") &&
                  cambio::perception::gaussian_half_width(1.4, 3.0) == 5;
  std::printf("consumer: %s\n", ok ? "ok" : "MISMATCH");
  return ok ? 0 : 1;
}
