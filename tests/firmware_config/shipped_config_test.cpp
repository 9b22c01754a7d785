// Tests of firmware_config/src/shipped_config.cpp: where the shipped YAML is found, and how a
// command-line config argument becomes a path.
#include "cambio/config/shipped_config.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "../scoped_environment_variable.hpp"
#include "cambio/config/config_error.hpp"
#include "cambio/config/rig_loader.hpp"

namespace cambio::config {
namespace {

TEST(ShippedConfig, FromTheBuildTreeTheSourceTreeServes) {
  if (std::getenv("CAMBIO_CONFIG_DIR") != nullptr) GTEST_SKIP() << "CAMBIO_CONFIG_DIR is set";
  EXPECT_EQ(shipped_config_dir(), std::string(CAMBIO_SOURCE_DIR) + "/firmware_config");
  EXPECT_EQ(find_shipped_config("perception/ssm.yaml"),
            std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/perception/ssm.yaml");
  EXPECT_NO_THROW(load_rig(find_shipped_config("rigs/cambio.yaml")));
}

TEST(ShippedConfig, MissingFileIsEmpty) {
  EXPECT_EQ(find_shipped_config("rigs/no_such_rig.yaml"), "");
}

TEST(ShippedConfig, EnvironmentVariableWinsForEveryKind) {
  const auto dir = std::filesystem::temp_directory_path() / "cambio_shipped_config_test";
  std::filesystem::create_directories(dir / "perception");
  std::ofstream(dir / "perception" / "ssm.yaml") << "rate_hz: 30\n";
  const cambio::testing::ScopedEnvironmentVariable override_dir("CAMBIO_CONFIG_DIR", dir.string());
  EXPECT_EQ(shipped_config_dir(), dir.string());
  EXPECT_EQ(find_shipped_config("perception/ssm.yaml"), (dir / "perception" / "ssm.yaml").string());
  EXPECT_EQ(find_shipped_config("rigs/cambio.yaml"), "");
}

TEST(ShippedConfig, AnEnvironmentVariableNamingNoDirectoryIsRefusedNotIgnored) {
  const auto file = std::filesystem::temp_directory_path() / "cambio_shipped_config_test_file";
  std::ofstream(file) << "not a directory\n";
  for (const std::string& value : {std::string("/nonexistent/cambio"), file.string()}) {
    const cambio::testing::ScopedEnvironmentVariable override_dir("CAMBIO_CONFIG_DIR", value);
    try {
      (void)find_shipped_config("perception/ssm.yaml");
      ADD_FAILURE() << value << " was taken";
    } catch (const ConfigError& error) {
      ASSERT_EQ(error.issues().size(), 1u);
      EXPECT_EQ(error.issues()[0].key_path, "CAMBIO_CONFIG_DIR");
      EXPECT_NE(error.issues()[0].message.find(value), std::string::npos) << error.what();
    }
  }
}

TEST(ResolveConfigArgument, AnExistingPathIsTakenAsGiven) {
  const auto dir = std::filesystem::temp_directory_path() / "cambio_shipped_config_test_path";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "cambio").string();  // Shadows the shipped rig's name.
  std::ofstream(path) << "rig: {}\n";
  EXPECT_EQ(resolve_config_argument("rigs", path), path);
}

TEST(ResolveConfigArgument, AShippedNameWithOrWithoutTheExtension) {
  const std::string rig = find_shipped_config("rigs/pan_tilt.yaml");
  ASSERT_FALSE(rig.empty());
  EXPECT_EQ(resolve_config_argument("rigs", "pan_tilt"), rig);
  EXPECT_EQ(resolve_config_argument("rigs", "pan_tilt.yaml"), rig);
  EXPECT_EQ(resolve_config_argument("scenes", "vergence"),
            find_shipped_config("scenes/vergence.yaml"));
}

TEST(ResolveConfigArgument, AnUnknownNameIsLeftForTheLoaderToReport) {
  EXPECT_EQ(resolve_config_argument("scenes", "no_such_scene"), "no_such_scene");
}

}  // namespace
}  // namespace cambio::config
