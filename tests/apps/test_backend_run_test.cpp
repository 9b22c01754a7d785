// The main job's loops on a backend that only this test knows: registered here, named by the rig
// (`--set rig.groups.pan_tilt.backend=test_rig`), run with no edit to the run assembly. The sim
// still renders the rig's camera and, modelling the whole robot, follows the test's joints.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "builtin_backends.hpp"
#include "cambio/config/config_error.hpp"
#include "cambio/config/experiment_config.hpp"
#include "cambio/sim/ground_truth.hpp"
#include "main_job.hpp"
#include "test_rig_backend.hpp"

namespace cambio::testing {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

config::ExperimentConfig pan_tilt_on(const std::string& backend) {
  return config::load_experiment(
      std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/experiments/pan_tilt_hold.yaml",
      {{"rig.groups.pan_tilt.backend", backend},
       {"experiment.executor", "lockstep"},
       {"experiment.duration_s", "0.5"}});
}

TEST(TestBackendRun, RunsTheMainJobsLoopsOnABackendRegisteredOutsideTheRunAssembly) {
  const config::ExperimentConfig experiment = pan_tilt_on("test_rig");
  hal::BackendFactory factory;
  app::register_builtin_backends(factory, experiment);
  TestRigRecord record;
  const double offset_rad = 3.0 * kDeg;
  register_test_rig_backend(factory, record, offset_rad);

  app::MainJob job(experiment, factory);
  EXPECT_FALSE(job.realtime()) << "a backend registered without traits is not paced by the wall";
  const std::atomic<bool> stop{false};
  const app::MainJobResult result = job.run(stop, [](double, double) {});

  EXPECT_EQ(record.configures, 1);
  EXPECT_EQ(record.activates, 1);
  EXPECT_GE(record.deactivates, 1);
  // The joint loop ran at its rate on the test's group, on the run's simulated clock.
  const double joint_rate_hz = experiment.rig.find_loop("joint")->rate_hz;
  EXPECT_NEAR(static_cast<double>(record.writes.load()), 0.5 * joint_rate_hz, 0.02 * joint_rate_hz);
  EXPECT_GE(record.reads.load(), record.writes.load());  // Each cycle reads, then writes.
  EXPECT_FALSE(result.fault_latched_at_end);
  EXPECT_EQ(result.watchdog_cycles, 0u);
  // The hold moved the joints from where they started (3 deg off) to the experiment's pose.
  EXPECT_NEAR(record.positions_rad.at("pan"), 10.0 * kDeg, 1e-6);
  EXPECT_NEAR(record.positions_rad.at("tilt"), -5.0 * kDeg, 1e-6);
  // The sim followed them: its world's joints (ground truth) are where the test's drives are,
  // and its camera kept rendering.
  sim::GroundTruth* truth = job.ground_truth();
  ASSERT_NE(truth, nullptr);
  EXPECT_NEAR(truth->joint_position_rad("pan"), 10.0 * kDeg, 1e-3);
  EXPECT_NEAR(truth->joint_position_rad("tilt"), -5.0 * kDeg, 1e-3);
  EXPECT_GT(result.camera_frames, 0u);
}

TEST(TestBackendRun, ABackendNoOneRegisteredIsRefusedAtItsKeyWithTheNamesAvailable) {
  const config::ExperimentConfig experiment = pan_tilt_on("test_rig");
  hal::BackendFactory factory;
  app::register_builtin_backends(factory, experiment);
  try {
    app::MainJob job(experiment, factory);
    FAIL() << "a rig naming an unregistered backend was built";
  } catch (const config::ConfigError& error) {
    ASSERT_EQ(error.issues().size(), 1u);
    EXPECT_EQ(error.issues()[0].key_path, "groups.pan_tilt.backend");
    EXPECT_NE(error.issues()[0].message.find("'test_rig' is not a known backend (available: "
                                             "sim, socketcan, v4l2)"),
              std::string::npos)
        << error.issues()[0].message;
  }
}

TEST(TestBackendRun, ATouchSensorOnABackendNoGroupOrCameraNamesIsMadeThereNotSkipped) {
  // The arms and cameras stay on the sim; one hand's touch sensor names the test's backend,
  // which has none: the run must ask it (and so refuse), not run without the sensor.
  const config::ExperimentConfig experiment = config::load_experiment(
      std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/experiments/reach_touch.yaml",
      {{"rig.touch_sensors.left_hand.backend", "test_rig"},
       {"rig.touch_sensors.right_hand.backend", "test_rig"}});
  hal::BackendFactory factory;
  app::register_builtin_backends(factory, experiment);
  TestRigRecord record;
  register_test_rig_backend(factory, record, 0.0);
  try {
    app::MainJob job(experiment, factory);
    const std::atomic<bool> stop{false};
    (void)job.run(stop, [](double, double) {});
    FAIL() << "a touch sensor its backend cannot make was skipped";
  } catch (const hal::BackendUnavailable& error) {
    EXPECT_NE(std::string(error.what()).find("test_rig has no touch sensor"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace cambio::testing
