// Scenes and cameras the generated MuJoCo model cannot hold are refused as config errors naming
// the key; scenes up to the documented limits (sim::kMaxSceneObjects, kMaxMovingObjects) build
// and step inside the arena the builder sizes for them.
#include <string>

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include "cambio/config/config_error.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/sim/mjcf_builder.hpp"
#include "cambio/sim/world.hpp"
#include "sim_test_support.hpp"

namespace cambio::sim {
namespace {

/// The ConfigError message of building `rig` in `scene`, or "accepted".
std::string refusal(const config::RigConfig& rig, const config::SceneConfig& scene) {
  try {
    World world(rig, scene);
  } catch (const config::ConfigError& error) {
    return error.what();
  }
  return "accepted";
}

config::SceneConfig scene_of(const std::string& yaml) {
  return config::load_scene_from_string(yaml, "limits.yaml");
}

/// `count` objects of one kind: small boxes on a 5 cm grid, free ones in a 10-wide block
/// dropped onto each other in layers, so they make many contacts while settling.
std::string objects(int count, const std::string& prefix, const std::string& body) {
  std::string yaml;
  for (int i = 0; i < count; ++i) {
    const bool free = body == "free";
    const double x = free ? 1.0 + (i % 5) * 0.021 : 1.0 + (i % 70) * 0.05;
    const double y = free ? (i / 5 % 5) * 0.021 : -1.75 + (i / 70 % 70) * 0.05;
    const double z = free ? 0.05 + (i / 25) * 0.03 : 0.5 + (i / 4900) * 0.1;
    yaml +=
        "  - {name: " + prefix + std::to_string(i) +
        ", shape: box, size_m: [0.02, 0.02, 0.02], xyz_m: [" + std::to_string(x) + ", " +
        std::to_string(y) + ", " + std::to_string(z) + "], rpy_deg: [10, 20, 5], body: " + body +
        (body == "scripted" ? ", motion: {type: oscillate, amplitude_m: 0.1, period_s: 1}" : "") +
        "}\n";
  }
  return yaml;
}

// Before: MuJoCo's "alternative specification error 'yaxis too small'" as a translation bug
// (exit 1).
TEST(SceneLimitsTest, AnOverviewCameraLookingAtItsOwnPositionIsAConfigError) {
  const std::string message =
      refusal(testing::load_shipped_rig(),
              scene_of("overview_camera: {xyz_m: [1, 2, 3], look_at_m: [1, 2, 3]}\n"));
  EXPECT_NE(message.find("limits.yaml: overview_camera.look_at_m: expected a point other than "
                         "the camera's own position [1, 2, 3], found [1, 2, 3]"),
            std::string::npos)
      << message;
}

// Before: MuJoCo's "repeated name in body array" (exit 1).
TEST(SceneLimitsTest, ObjectsNamedLikeTheRobotOrTheWorldAreConfigErrors) {
  const std::string message =
      refusal(testing::load_shipped_rig(),
              scene_of("objects:\n"
                       "  - {name: neck_pan, shape: sphere, radius_m: 0.1, xyz_m: [1, 0, 1]}\n"
                       "  - {name: torso, shape: sphere, radius_m: 0.1, xyz_m: [1, 1, 1]}\n"
                       "  - {name: left_gripper_mimic, shape: sphere, radius_m: 0.1, "
                       "xyz_m: [1, 2, 1]}\n"));
  EXPECT_NE(message.find("objects[0].name: 'neck_pan' is already the name of a joint of rig"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("objects[1].name: 'torso' is already the name of a part of the"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("objects[2].name"), std::string::npos) << message;
}

// Before: MuJoCo's "mass and inertia of moving bodies must be larger than mjMINVAL" as a
// translation bug (exit 1). Any element MuJoCo refuses that came from an object names it.
TEST(SceneLimitsTest, AnObjectMuJoCoRefusesIsNamed) {
  const std::string message = refusal(
      testing::load_shipped_rig(),
      scene_of("objects:\n"
               "  - {name: ball, shape: sphere, radius_m: 0.1, xyz_m: [1, 0, 1]}\n"
               "  - {name: dust, shape: sphere, radius_m: 1.0e-7, xyz_m: [1, 0, 1], body: free, "
               "mass_kg: 1.0e-9}\n"));
  EXPECT_NE(message.find("limits.yaml: objects[1]: MuJoCo cannot build it: mass and inertia"),
            std::string::npos)
      << message;
}

// Before: a 65535-px camera (the config's limit) ended in "Offscreen framebuffer is not
// complete" (exit 1).
TEST(SceneLimitsTest, CamerasTheSimCannotRenderAreConfigErrors) {
  auto rig = testing::load_shipped_rig();
  rig.cameras[0].width_px = kMaxCameraSidePx + 1;
  rig.cameras[0].principal_x_px = (rig.cameras[0].width_px - 1) / 2.0;
  rig.cameras[1].height_px = 65535;
  rig.cameras[1].principal_y_px = (65535 - 1) / 2.0;
  const std::string message = refusal(rig, testing::empty_scene());
  EXPECT_NE(message.find("cameras.left_eye.width_px: the simulator renders cameras of at most "
                         "4096 px a side, found 4097"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("cameras.right_eye.height_px"), std::string::npos) << message;
  rig = testing::load_shipped_rig();
  rig.cameras[0].name = kOverviewCameraName;
  EXPECT_NE(refusal(rig, testing::empty_scene()).find("cameras.overview: 'overview' is the name"),
            std::string::npos);
}

TEST(SceneLimitsTest, ScenesPastTheObjectLimitsAreConfigErrors) {
  const auto rig = testing::load_shipped_rig();
  // The loader refuses such a scene first; a scene built in code meets the sim's own check.
  config::SceneConfig crowded = scene_of("objects:\n" + objects(kMaxSceneObjects, "s", "static"));
  crowded.objects.push_back(crowded.objects.back());
  crowded.objects.back().name = "one_too_many";
  std::string message = refusal(rig, crowded);
  EXPECT_NE(message.find("objects: the simulator holds at most " +
                         std::to_string(kMaxSceneObjects) + " objects"),
            std::string::npos)
      << message;
  message = refusal(rig, scene_of("objects:\n" + objects(kMaxMovingObjects, "f", "free") +
                                  objects(1, "m", "scripted")));
  EXPECT_NE(message.find("objects: the simulator moves at most 100 free or scripted objects"),
            std::string::npos)
      << message;
}

// Before: 2000 static objects overflowed MuJoCo's stack while compiling (its estimate ignores the
// broad phase), 2000 free ones asked for 6 GB of stack, and 100 contacts (nconmax) dropped the
// rest, so free objects fell through the floor. At the limits, the model builds, the pile of
// free boxes settles on the floor with every contact kept, and the stack is never short.
TEST(SceneLimitsTest, AScenePackedToTheLimitsBuildsAndSteps) {
  const auto scene = scene_of("objects:\n" + objects(kMaxMovingObjects, "f", "free") +
                              objects(kMaxSceneObjects - kMaxMovingObjects, "s", "static"));
  World world(testing::load_shipped_rig(), scene);
  mjModel* model = world.model();
  mjData* data = world.data();
  for (int step = 0; step < 600; ++step) mj_step(model, data);
  EXPECT_EQ(data->warning[mjWARN_CONTACTFULL].number, 0);
  EXPECT_EQ(data->warning[mjWARN_CNSTRFULL].number, 0);
  EXPECT_GT(data->maxuse_con, kMaxMovingObjects) << "the pile touches itself and the floor";
  // The broad phase takes most of it (nbody^2 / 2); the rest is the solver's.
  EXPECT_LT(data->maxuse_stack, 0.9 * model->nstack) << "nstack " << model->nstack;
  for (const auto& object : world.objects()) {
    if (object.qpos_address < 0) continue;
    EXPECT_GT(data->qpos[object.qpos_address + 2], 0.0) << object.name << " fell through";
  }
}

}  // namespace
}  // namespace cambio::sim
