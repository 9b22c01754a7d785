#pragma once

#include <array>
#include <string>
#include <vector>

#include "cambio/config/rig_config.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/scene_config.hpp"

namespace cambio::sim {

/// A texture the MJCF declares as a flat placeholder and the world fills with a procedural
/// pattern after compiling (MJCF 2.2 cannot carry generated pixels).
struct ProceduralTextureSpec {
  std::string texture_name;  ///< MJCF texture name.
  config::TextureConfig texture;
  std::array<double, 3> rgb{};
  double feature_px = 8.0;  ///< Feature size in texels.
};

/// The MJCF text for a rig in a scene, and the procedural textures to fill in.
struct GeneratedModel {
  std::string xml;
  std::vector<ProceduralTextureSpec> textures;
};

struct MjcfOptions {
  /// Offscreen framebuffer size; 0 means "the largest camera of the rig". Larger renders (the
  /// overview) need it raised.
  int offscreen_width_px = 0;
  int offscreen_height_px = 0;
};

/// The largest camera image the sim renders, in pixels a side: the rig loader's limit
/// (config::kMaxCameraSide_px), checked again here for rigs built in code. Each camera renders
/// into one offscreen framebuffer (4 bytes of colour and 4 of depth a pixel) and is read back into
/// two RGB buffers. GL implementations may allow less (GL_MAX_RENDERBUFFER_SIZE); the renderer
/// checks that too. Larger cameras are refused with a ConfigError naming them.
inline constexpr int kMaxCameraSidePx = config::kMaxCameraSide_px;

/// Scene objects in all: the scene loader's limit (config::kMaxSceneObjects), checked again here
/// for scenes built in code. MuJoCo's broad phase takes nbody^2 / 2 numbers of its stack (mjData's
/// arena, sized from the model by build_mjcf); the arena sizing was measured up to 5000 objects.
inline constexpr int kMaxSceneObjects = static_cast<int>(config::kMaxSceneObjects);
/// Objects that move (free or scripted). Each free one adds 6 degrees of freedom, and MuJoCo
/// 2.2's Newton solver keeps dense nv x nv matrices (5 nv^2 numbers of stack); each may touch
/// others and the robot in 8 contacts of 4 constraint rows, whose nefc x nefc matrix mjData
/// allocates at once. At 100: nv 617, 900 contacts, 3700 rows, 110 MB.
inline constexpr int kMaxMovingObjects = 100;

/// MJCF geom groups. The eyes render groups 0-2; group 3 (the head that carries the cameras)
/// is drawn only by third-person views, so an eye never sees its own housing.
inline constexpr int kSceneGeomGroup = 0;
inline constexpr int kRobotGeomGroup = 1;
/// The eyes' cheap sky planes; third-person views draw MuJoCo's skybox instead.
inline constexpr int kEyeSkyGeomGroup = 2;
inline constexpr int kHiddenFromEyesGeomGroup = 3;

/// Name of the third-person camera generated from the scene's overview_camera.
inline constexpr const char* kOverviewCameraName = "overview";
/// Suffix of the generated second finger of a gripper (coupled to the gripper joint, mirrored).
inline constexpr const char* kMimicSuffix = "_mimic";

/// The generated fingers (a touch sensor's gripper) end at the rig's fingertip_xy_m: half the
/// fingertip pad's thickness along the finger, and the beam's offset outward of the pad.
inline constexpr double kFingerPadHalf_m = 0.004;
inline constexpr double kFingerBeamOffset_m = 0.006;

/// True for joints that carry a camera (the neck and eye joints of the head): the sim drives
/// them kinematically from the servo model. Every other joint is driven through physics.
bool carries_camera(const config::RigConfig& rig, const std::string& joint_name);

/// Checks what MuJoCo's pinhole can represent: square pixels (focal_x == focal_y), a centred
/// principal point (cx = (width - 1) / 2, cy = (height - 1) / 2), at most kMaxCameraSidePx a
/// side, a name other than the overview's. Throws config::ConfigError naming each offending
/// camera key.
void check_cameras_representable(const config::RigConfig& rig);

/// Checks what the generated model can hold: at most kMaxSceneObjects objects and
/// kMaxMovingObjects moving ones, object names apart from the names the model gives the robot
/// and its surroundings (joints, "floor", "torso", ...), an overview camera that looks at a point
/// other than its own position. Throws config::ConfigError naming each offending key.
void check_scene_representable(const config::RigConfig& rig, const config::SceneConfig& scene);

/// Generates the MJCF: the robot's links, joints, cameras and actuators from the rig; the
/// objects, textures and lights from the scene. The only description of the world. MuJoCo's
/// arena (stack, contacts, constraint rows) is sized from the counts of bodies and degrees of
/// freedom. Throws config::ConfigError for cameras and scenes the model cannot represent (see
/// the checks above) and std::runtime_error for a rig whose kinematic tree is broken (a parent
/// that is not a joint).
GeneratedModel build_mjcf(const config::RigConfig& rig, const config::SceneConfig& scene,
                          const MjcfOptions& options = {});

}  // namespace cambio::sim
