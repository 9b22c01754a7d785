// Tests of firmware_config/src/experiment_loader.cpp.
#include "cambio/config/experiment_config.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "rig_test_support.hpp"

namespace cambio::config {
namespace {

TEST(ExperimentLoader, VergenceKeysLeftOutTakeTheConfigDefaults) {
  const auto dir = std::filesystem::temp_directory_path() / "cambio_experiment_loader_test";
  std::filesystem::create_directories(dir);
  const auto path = dir / "vergence_defaults.yaml";
  std::ofstream(path) << "experiment:\n"
                      << "  name: defaults\n"
                      << "  rig: " << test::shipped_rig_path("cambio.yaml") << "\n"
                      << "  duration_s: 1\n"
                      << "  task: vergence\n"
                      << "  vergence: {verging_eye: left, gain: 0.25}\n";
  const ExperimentConfig experiment = load_experiment(path.string());
  const VergenceTaskConfig defaults;
  EXPECT_EQ(experiment.vergence.verging_eye, hal::Eye::kLeft);
  EXPECT_EQ(experiment.vergence.gain, 0.25);
  EXPECT_EQ(experiment.vergence.min_confidence, defaults.min_confidence);
  EXPECT_EQ(experiment.vergence.max_step_rad, defaults.max_step_rad);
  EXPECT_EQ(experiment.vergence.goal_disparity_px, defaults.goal_disparity_px);
}

}  // namespace
}  // namespace cambio::config
