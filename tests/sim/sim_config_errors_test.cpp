// Bad scene and rig input is refused with a message that says where and what.
#include <string>

#include <gtest/gtest.h>

#include "cambio/config/config_error.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/sim/mujoco_error.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "sim_test_support.hpp"

#include <mujoco/mujoco.h>

namespace cambio::sim {
namespace {

std::string scene_error(const std::string& yaml) {
  try {
    config::load_scene_from_string(yaml, "bad_scene.yaml");
  } catch (const config::ConfigError& error) {
    return error.what();
  }
  return "no error";
}

TEST(SceneErrorsTest, UnknownShapeIsReportedAtItsLine) {
  const std::string message = scene_error(
      "objects:\n"
      "  - name: thing\n"
      "    shape: pyramid\n"
      "    radius_m: 0.1\n"
      "    xyz_m: [1, 0, 1]\n");
  EXPECT_NE(message.find("bad_scene.yaml:3:"), std::string::npos) << message;
  EXPECT_NE(message.find("pyramid"), std::string::npos) << message;
  EXPECT_NE(message.find("sphere"), std::string::npos) << "lists the allowed shapes: " << message;
}

TEST(SceneErrorsTest, NegativeSizeIsReportedAtItsLine) {
  const std::string message = scene_error(
      "objects:\n"
      "  - name: ball\n"
      "    shape: sphere\n"
      "    radius_m: -0.1\n"
      "    xyz_m: [1, 0, 1]\n");
  EXPECT_NE(message.find("bad_scene.yaml:4:"), std::string::npos) << message;
  EXPECT_NE(message.find("radius_m"), std::string::npos) << message;
  const std::string box = scene_error(
      "objects:\n"
      "  - {name: box, shape: box, size_m: [0.1, -0.2, 0.1], xyz_m: [1, 0, 1]}\n");
  EXPECT_NE(box.find("bad_scene.yaml:2:"), std::string::npos) << box;
}

TEST(SceneErrorsTest, UnknownTextureIsReportedAtItsLine) {
  const std::string message = scene_error(
      "objects:\n"
      "  - name: ball\n"
      "    shape: sphere\n"
      "    radius_m: 0.1\n"
      "    xyz_m: [1, 0, 1]\n"
      "    texture: {type: marble}\n");
  EXPECT_NE(message.find("bad_scene.yaml:6:"), std::string::npos) << message;
  EXPECT_NE(message.find("marble"), std::string::npos) << message;
  EXPECT_NE(message.find("noise"), std::string::npos) << message;
}

TEST(SceneErrorsTest, AChessboardNeedsItsSquaresAndABoxWithASquareFaceItFits) {
  const auto board = [](const std::string& shape, const std::string& texture) {
    return scene_error("objects:\n  - name: board\n    " + shape +
                       "\n    xyz_m: [1, 0, 1]\n    texture: " + texture + "\n");
  };
  const std::string fine = "{type: chessboard, squares: [10, 7], feature_size_m: 0.025}";
  EXPECT_EQ(board("shape: box\n    size_m: [0.01, 0.3, 0.3]", fine), "no error");
  std::string message = board("shape: box\n    size_m: [0.01, 0.3, 0.3]",
                              "{type: chessboard, feature_size_m: 0.025}");
  EXPECT_NE(message.find("squares"), std::string::npos) << message;
  message = board("shape: box\n    size_m: [0.01, 0.3, 0.3]",
                  "{type: chessboard, squares: [10.5, 7], feature_size_m: 0.025}");
  EXPECT_NE(message.find("two whole numbers of squares"), std::string::npos) << message;
  message = board("shape: box\n    size_m: [0.01, 0.3, 0.2]", fine);
  EXPECT_NE(message.find("bad_scene.yaml:6:"), std::string::npos) << message;
  EXPECT_NE(message.find("a box with a square face"), std::string::npos) << message;
  message = board("shape: sphere\n    radius_m: 0.2", fine);
  EXPECT_NE(message.find("a box with a square face"), std::string::npos) << message;
  message = board("shape: box\n    size_m: [0.01, 0.2, 0.2]", fine);
  EXPECT_NE(message.find("is larger than the box's face (0.2"), std::string::npos) << message;
  message = scene_error("world:\n  floor_texture: " + fine + "\n");
  EXPECT_NE(message.find("not the floor"), std::string::npos) << message;
}

TEST(SceneErrorsTest, EveryProblemIsReportedAtOnce) {
  try {
    config::load_scene_from_string(
        "objects:\n"
        "  - {name: a, shape: cone, xyz_m: [1, 0, 1]}\n"
        "  - {name: a, shape: sphere, radius_m: 0, xyz_m: [1, 0, 1]}\n"
        "  - {name: b, shape: box, size_m: [1, 1, 1], xyz_m: [1, 0, 1], colour: [1, 0, 0]}\n"
        "  - {name: c, shape: sphere, radius_m: 0.1, xyz_m: [1, 0, 1], motion: {type: circle, "
        "radius_m: 0.1, period_s: 1}}\n",
        "many.yaml");
    FAIL() << "accepted";
  } catch (const config::ConfigError& error) {
    EXPECT_GE(error.issues().size(), 5u) << error.what();
    const std::string message = error.what();
    EXPECT_NE(message.find("duplicate"), std::string::npos) << message;
    EXPECT_NE(message.find("colour"), std::string::npos) << message;
    EXPECT_NE(message.find("scripted"), std::string::npos) << message;
  }
}

TEST(SceneErrorsTest, ShippedScenesLoad) {
  for (const char* name : {"vergence", "distractors", "saccade", "table"}) {
    EXPECT_NO_THROW(testing::load_shipped_scene(name)) << name;
  }
}

TEST(RigErrorsTest, CameraWithOffCentrePrincipalPointIsRefusedAtConfigTime) {
  auto rig = testing::load_shipped_rig();
  rig.cameras[0].principal_x_px = 300.0;
  rig.cameras[1].focal_y_px = rig.cameras[1].focal_x_px * 1.01;
  try {
    hal::ManualClock clock;
    auto backend = testing::make_sim(rig, testing::load_shipped_scene("vergence"), clock);
    FAIL() << "accepted";
  } catch (const config::ConfigError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("cameras.left_eye.principal_point_px"), std::string::npos) << message;
    EXPECT_NE(message.find("319.5"), std::string::npos) << "says what it expected: " << message;
    EXPECT_NE(message.find("cameras.right_eye.focal_px"), std::string::npos) << message;
  }
}

TEST(RigErrorsTest, ASimCameraWithALensItCannotRenderIsRefusedARealOneBesideTheSimIsNot) {
  auto rig = testing::load_shipped_rig();
  // A plausible lens renders (SimLens); one that folds back inside the frame cannot.
  rig.cameras[0].distortion.k1 = -0.2;
  {
    hal::ManualClock clock;
    EXPECT_NO_THROW(testing::make_sim(rig, testing::load_shipped_scene("vergence"), clock));
  }
  rig.cameras[0].distortion.k1 = -2.2;
  try {
    hal::ManualClock clock;
    auto backend = testing::make_sim(rig, testing::load_shipped_scene("vergence"), clock);
    FAIL() << "accepted a sim camera whose lens folds over inside the image";
  } catch (const config::ConfigError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("cameras.left_eye.distortion"), std::string::npos) << message;
    EXPECT_NE(message.find("k1 -2.2"), std::string::npos) << message;
  }
  // A calibrated V4L2 eye (off-centre principal point, that lens) beside sim joints: the sim
  // does not render it, so it takes it as it is.
  rig.cameras[0].backend = "v4l2";
  rig.cameras[0].principal_x_px += 7.25;
  hal::ManualClock clock;
  EXPECT_NO_THROW(testing::make_sim(rig, testing::load_shipped_scene("vergence"), clock));
}

TEST(RigErrorsTest, BrokenKinematicTreeIsRefused) {
  auto rig = testing::load_shipped_rig();
  rig.joints[1].parent = "no_such_link";
  hal::ManualClock clock;
  // Built by hand: the hardware description would refuse the broken tree before the sim sees it.
  EXPECT_THROW(SimBackend(rig, testing::load_shipped_scene("vergence"), hal::HardwareInfo{},
                          hal::BackendContext{&clock}),
               std::runtime_error);
}

TEST(MujocoErrorTest, MujocoErrorsBecomeExceptionsNotPrompts) {
  install_mujoco_handlers();
  EXPECT_THROW(mju_error("simulated failure"), MujocoError);
  try {
    mju_error("simulated failure");
  } catch (const MujocoError& error) {
    EXPECT_NE(std::string(error.what()).find("simulated failure"), std::string::npos);
  }
  const auto warnings = mujoco_warning_count();
  mju_warning("a warning");
  EXPECT_EQ(mujoco_warning_count(), warnings + 1);
  EXPECT_EQ(last_mujoco_warning(), "a warning");
}

}  // namespace
}  // namespace cambio::sim
