// The SSM config loader: the shipped file holds the defaults; mistakes are reported with their
// position and a suggestion.
#include "cambio/perception/perception_config.hpp"

#include <gtest/gtest.h>

#include "cambio/config/map_reader.hpp"
#include "cambio/perception/sensory_servo.hpp"

namespace cambio::perception {
namespace {

SsmConfig from_text(const std::string& text) {
  config::ConfigDocument document = config::ConfigDocument::from_string(text, "ssm.yaml");
  config::MapReader root = document.root();
  SsmConfig loaded = read_ssm_config(root);
  document.issues()->throw_if_any();
  return loaded;
}

std::string all_messages(const config::ConfigError& error) {
  std::string text;
  for (const auto& issue : error.issues()) text += issue.to_string() + "\n";
  return text;
}

TEST(PerceptionConfig, ShippedFileIsTheDefaults) {
  const std::string path = default_ssm_config_path();
  ASSERT_FALSE(path.empty());
  const SsmConfig loaded = load_ssm_config(path, {});
  const SsmConfig defaults;
  EXPECT_EQ(loaded.retina.levels, defaults.retina.levels);
  EXPECT_EQ(loaded.retina.width_px, defaults.retina.width_px);
  // The one departure from the built-in defaults: the paper's field-covering coarsest level.
  EXPECT_TRUE(loaded.retina.coarsest_covers_field);
  EXPECT_EQ(loaded.operators.sigmas_px, defaults.operators.sigmas_px);
  EXPECT_EQ(loaded.operators.half_width_sigmas, defaults.operators.half_width_sigmas);
  EXPECT_EQ(loaded.disparity.features, defaults.disparity.features);
  EXPECT_EQ(loaded.disparity.search_range_px, defaults.disparity.search_range_px);
  EXPECT_EQ(loaded.motion.iterations, defaults.motion.iterations);
  EXPECT_EQ(loaded.moments.map, defaults.moments.map);
  EXPECT_EQ(loaded.moments.mode, defaults.moments.mode);
  EXPECT_EQ(loaded.region.cells, defaults.region.cells);
  EXPECT_EQ(loaded.region.cell_px, defaults.region.cell_px);
  EXPECT_EQ(loaded.region.max_disparity_px, defaults.region.max_disparity_px);
  EXPECT_EQ(loaded.region.min_correlation, defaults.region.min_correlation);
}

TEST(PerceptionConfig, TheFixatedRegionsSettingsAreReadAndCheckedByName) {
  const SsmConfig c = from_text("region: {cells: 24, cell_px: 6, max_disparity_px: 3}\n");
  EXPECT_EQ(c.region.cells, 24);
  EXPECT_EQ(c.region.cell_px, 6);
  EXPECT_EQ(c.region.max_disparity_px, 3);
  try {
    from_text("region: {cells: 1, min_correlation: 1.5}\n");
    FAIL() << "a one-cell window and a correlation above 1 were accepted";
  } catch (const config::ConfigError& error) {
    const std::string text = all_messages(error);
    EXPECT_NE(text.find("region.cells"), std::string::npos) << text;
    EXPECT_NE(text.find("region.min_correlation"), std::string::npos) << text;
  }
}

TEST(PerceptionConfig, ReadsMasksAndOverrides) {
  const SsmConfig c = from_text(
      "retina: {levels: 3, width_px: 64, height_px: 48}\n"
      "operators:\n"
      "  sigmas_px: [1.7]\n"
      "  half_width_px: 3\n"
      "  masks:\n"
      "    - {name: prewitt_x, rows: 3, cols: 3, values: [-1, 0, 1, -1, 0, 1, -1, 0, 1]}\n"
      "disparity: {features: [g2x@1.7, log@1.7]}\n"
      "moments: {map: prewitt_x, mode: weighted, threshold: 0}\n");
  EXPECT_EQ(c.retina.levels, 3);
  EXPECT_EQ(c.retina.height_px, 48);
  EXPECT_EQ(c.operators.half_width_px, 3);
  ASSERT_EQ(c.operators.masks.size(), 1u);
  EXPECT_EQ(c.operators.masks[0].values.size(), 9u);
  EXPECT_EQ(c.moments.mode, MomentsConfig::Mode::kWeighted);
}

TEST(PerceptionConfig, ReportsEveryMistakeWithPositionAndSuggestion) {
  try {
    from_text(
        "retina: {levels: 12, widht_px: 16}\n"
        "operators:\n"
        "  masks:\n"
        "    - {name: m, rows: 2, cols: 3, values: [1, 2, 3, 4, 5, 6]}\n"
        "disparity: {features: [g2x@1.5]}\n");
    FAIL() << "expected a ConfigError";
  } catch (const config::ConfigError& error) {
    const std::string text = all_messages(error);
    EXPECT_NE(text.find("ssm.yaml:1:"), std::string::npos) << text;
    EXPECT_NE(text.find("retina.levels"), std::string::npos) << text;
    EXPECT_NE(text.find("did you mean \"width_px\""), std::string::npos) << text;
    EXPECT_NE(text.find("odd rows and cols"), std::string::npos) << text;
    EXPECT_NE(text.find("did you mean \"g2x@1.4\""), std::string::npos) << text;
    EXPECT_GE(error.issues().size(), 4u);
  }
}

// Found by fuzz_perception (tests/fuzz/regressions/fuzz_perception/): a disparity section that
// set other keys let the default features through unchecked, and the SSM threw while building.
TEST(PerceptionConfig, DefaultDisparityFeaturesMustExistWhateverTheDisparitySectionSets) {
  for (const std::string disparity :
       {"", "disparity: {search_range_px: 96}\n", "disparity: {enabled: false}\n"}) {
    try {
      from_text("operators: {sigmas_px: [2.7, 4.0]}\n" + disparity);
      FAIL() << "expected a ConfigError for: " << disparity;
    } catch (const config::ConfigError& error) {
      const std::string text = all_messages(error);
      EXPECT_NE(text.find("the default disparity feature \"g2x@1.4\""), std::string::npos) << text;
      EXPECT_NE(text.find("set disparity.features"), std::string::npos) << text;
    }
  }
  // Naming features of the operator set is the way out, and what loads builds an SSM.
  const SsmConfig c = from_text(
      "operators: {sigmas_px: [2.7, 4.0]}\n"
      "disparity: {search_range_px: 96, features: [g2x@2.7]}\n");
  EXPECT_NO_THROW(SensoryServo(c, 320, 240));
}

}  // namespace
}  // namespace cambio::perception
