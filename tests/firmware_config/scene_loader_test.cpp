// Tests of firmware_config/src/scene_loader.cpp: the bounds on what a scene may hold.
#include <gtest/gtest.h>

#include <string>

#include "cambio/config/scene_config.hpp"
#include "rig_test_support.hpp"

namespace cambio::config {
namespace {

std::string scene_with_objects(std::size_t count) {
  std::string yaml = "objects:\n";
  for (std::size_t i = 0; i < count; ++i) {
    yaml += "  - {name: ball" + std::to_string(i) + ", shape: sphere, radius_m: 0.01, xyz_m: [" +
            std::to_string(i) + ", 0, 1]}\n";
  }
  return yaml;
}

TEST(SceneLimits, ObjectCount) {
  EXPECT_EQ(
      load_scene_from_string(scene_with_objects(kMaxSceneObjects), "scene.yaml").objects.size(),
      kMaxSceneObjects);
  try {
    load_scene_from_string(scene_with_objects(kMaxSceneObjects + 1), "scene.yaml");
    FAIL() << "expected the scene to be refused";
  } catch (const ConfigError& error) {
    ASSERT_EQ(error.issues().size(), 1u) << error.what();
    EXPECT_EQ(error.issues()[0].to_string(),
              "scene.yaml:2:3: objects: expected at most 1000 objects (each is a body the sim "
              "collides every physics step, sized into MuJoCo's arena at load), found 1001");
  }
}

TEST(SceneLimits, ShippedScenesAreWellWithin) {
  for (const char* name : {"vergence", "saccade", "distractors", "table"}) {
    const SceneConfig scene =
        load_scene(find_shipped_config(std::string("scenes/") + name + ".yaml"));
    EXPECT_LE(scene.objects.size(), 10u) << name;
  }
}

}  // namespace
}  // namespace cambio::config
