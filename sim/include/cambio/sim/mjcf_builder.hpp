#pragma once

#include <array>
#include <string>
#include <vector>

#include "cambio/config/rig_config.hpp"
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

/// The largest camera image the sim renders, in pixels a side. Each camera renders into one
/// offscreen framebuffer (4 bytes of colour and 4 of depth a pixel) and is read back into two
/// RGB buffers: at 8192 x 8192 that is 940 MB per camera. GL implementations may allow less
/// (GL_MAX_RENDERBUFFER_SIZE); the renderer checks that too. Larger cameras are refused with a
/// ConfigError naming them.
inline constexpr int kMaxCameraSidePx = 8192;

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

/// True for joints that carry a camera (the neck and eye joints of the head): the sim drives
/// them kinematically from the servo model. Every other joint is driven through physics.
bool carries_camera(const config::RigConfig& rig, const std::string& joint_name);

/// Checks what MuJoCo's pinhole can represent: square pixels (focal_x == focal_y) and a centred
/// principal point (cx = (width - 1) / 2, cy = (height - 1) / 2). Throws config::ConfigError
/// naming each offending camera key.
void check_cameras_representable(const config::RigConfig& rig);

/// Generates the MJCF: the robot's links, joints, cameras and actuators from the rig; the
/// objects, textures and lights from the scene. The only description of the world. Throws
/// config::ConfigError for cameras MuJoCo cannot render and std::runtime_error for a rig whose
/// kinematic tree is broken (a parent that is not a joint).
GeneratedModel build_mjcf(const config::RigConfig& rig, const config::SceneConfig& scene,
                          const MjcfOptions& options = {});

}  // namespace cambio::sim
