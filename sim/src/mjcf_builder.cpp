// MJCF generation: the rig and the scene are the only description of the world; this turns them
// into one MuJoCo model. Link shapes are derived from the kinematics (a capsule from each joint
// to each child joint), so a rig file needs no separate geometry.
#include "cambio/sim/mjcf_builder.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>

#include "cambio/config/config_error.hpp"
#include "sim_lens.hpp"

namespace cambio::sim {

namespace {

hal::CameraIntrinsics intrinsics_of(const config::CameraConfig& camera) {
  return {camera.width_px,   camera.height_px,      camera.focal_x_px,
          camera.focal_y_px, camera.principal_x_px, camera.principal_y_px};
}

using config::CameraConfig;
using config::JointConfig;
using config::RigConfig;
using config::SceneConfig;
using config::SceneObjectConfig;
using config::ShapeKind;
using config::TextureKind;

// Cube-map face size bounds (texels) and texels per feature for generated textures.
constexpr int kMinFacePx = 32;
constexpr int kMaxFacePx = 512;
constexpr double kTexelsPerFeature = 12.0;
/// A chessboard's squares: enough texels that its corners are found to a tenth of a pixel
/// at calibration distances (a 25 mm square half a metre away spans about 28 px).
constexpr double kTexelsPerChessboardSquare = 40.0;
constexpr int kTiledTexturePx = 256;

Eigen::Matrix3d rotation_from_rpy(const std::array<double, 3>& rpy) {
  return (Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy[0], Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// Numbers with enough digits that a round trip through the XML loses nothing that matters
// (sub-micrometre, sub-microradian).
std::string num(double value) {
  std::ostringstream out;
  out << std::setprecision(12) << value;
  return out.str();
}
std::string vec(const Eigen::Vector3d& v) {
  return num(v.x()) + " " + num(v.y()) + " " + num(v.z());
}
std::string vec(const std::array<double, 3>& v) {
  return num(v[0]) + " " + num(v[1]) + " " + num(v[2]);
}
std::string quat(const Eigen::Matrix3d& rotation) {
  const Eigen::Quaterniond q(rotation);
  return num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z());
}
std::string rgba(const std::array<double, 3>& rgb, double alpha = 1.0) {
  return vec(rgb) + " " + num(alpha);
}

// XML attribute values come from user names; escape what XML requires.
std::string xml_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

class Builder {
 public:
  Builder(const RigConfig& rig, const SceneConfig& scene, const MjcfOptions& options)
      : rig_(rig), scene_(scene), options_(options) {}

  GeneratedModel build() {
    index_tree();
    std::ostringstream xml;
    xml << "<mujoco model=\"" << xml_escape(rig_.name + "_in_" + scene_.name) << "\">\n";
    xml << "  <compiler angle=\"radian\" inertiafromgeom=\"true\"/>\n";
    write_size(xml);
    // Euler, Newton solver with a modest iteration cap (the contacts are few: hands, objects,
    // table). Sparse Jacobians: the robot is three short chains and a few free bodies, so the
    // mass matrix is block-sparse (measured 20% faster than dense for the full robot).
    xml << "  <option timestep=\"" << num(1.0 / rig_.sim.physics_rate_hz)
        << "\" gravity=\"0 0 -9.81\" integrator=\"Euler\" jacobian=\"sparse\" iterations=\"30\" "
           "tolerance=\"1e-8\"/>\n";
    write_visual(xml);
    xml << "  <statistic extent=\"2\" center=\"0.5 0 1\"/>\n";
    write_defaults(xml);
    write_assets(xml);
    xml << "  <worldbody>\n";
    write_world(xml);
    write_link_children(xml, "base", 2);
    write_objects(xml);
    xml << "  </worldbody>\n";
    write_equalities(xml);
    write_actuators(xml);
    xml << "</mujoco>\n";
    model_.xml = xml.str();
    return std::move(model_);
  }

 private:
  void index_tree() {
    std::set<std::string> names;
    for (const auto& joint : rig_.joints) names.insert(joint.name);
    for (const auto& joint : rig_.joints) {
      if (joint.parent != "base" && names.count(joint.parent) == 0) {
        throw std::runtime_error("rig " + rig_.source_file + ": joint '" + joint.name +
                                 "' hangs from '" + joint.parent +
                                 "', which is neither 'base' nor a joint");
      }
      children_[joint.parent].push_back(&joint);
    }
    for (const auto& sensor : rig_.touch_sensors) hands_.emplace(sensor.parent, &sensor);
  }

  // MuJoCo 2.2 sizes mjData's stack as 5 (njmax + nv)^2 + O(n) numbers (MuJoCo's own
  // estimate), with nothing for the broad phase's nbody^2 / 2: a scene of 2000 static objects
  // overflowed it while compiling, and raising njmax for many contacts makes the estimate grow by
  // gigabytes. Sized here from what the model holds instead, each term measured on 2.2.2 (its
  // maxuse_stack; tests/sim/sim_scene_limits_test.cpp checks the largest scenes): the broad
  // phase, the Newton solver's dense nv x nv matrices, and vectors over constraint rows, bodies
  // and degrees of freedom. Every moving object may make 8 contacts of 4 rows (condim 3,
  // pyramidal cone) beyond the robot's 100 contacts and 500 rows that the defaults gave.
  void write_size(std::ostringstream& xml) {
    long long free = 0;
    long long moving = 0;
    for (const auto& object : scene_.objects) {
      free += object.body == config::BodyKind::kFree ? 1 : 0;
      moving += object.body != config::BodyKind::kStatic ? 1 : 0;
    }
    const auto joints = static_cast<long long>(rig_.joints.size());
    // The world, a link per joint and at most one mirrored finger per joint, the objects.
    const long long bodies = 1 + 2 * joints + static_cast<long long>(scene_.objects.size());
    const long long dofs = 2 * joints + 6 * free;
    const long long contacts = 100 + 8 * moving;
    const long long rows = 500 + 4 * 8 * moving;
    const long long stack =
        bodies * bodies / 2 + 5 * dofs * dofs + 100 * (rows + bodies + dofs) + 100'000;
    xml << "  <size nstack=\"" << stack << "\" nconmax=\"" << contacts << "\" njmax=\"" << rows
        << "\"/>\n";
  }

  void write_visual(std::ostringstream& xml) {
    int width = options_.offscreen_width_px;
    int height = options_.offscreen_height_px;
    for (const auto& camera : rig_.cameras) {
      width = std::max(width, camera.width_px);
      height = std::max(height, camera.height_px);
      // A camera with a lens renders its ideal view over a wider window (SimLens).
      if (camera.backend == "sim" && !camera.distortion.is_zero()) {
        if (const auto window = SimLens::ideal_window(intrinsics_of(camera), camera.distortion)) {
          width = std::max(width, window->width_px);
          height = std::max(height, window->height_px);
        }
      }
    }
    width = std::max(width, 64);
    height = std::max(height, 64);
    // znear/zfar are fractions of the extent (2 m): 1 cm to 50 m. Depth resolution at 1 m is
    // then about 6 um with a 24-bit depth buffer, well inside the 1 mm depth requirement.
    xml << "  <visual>\n"
        << "    <global offwidth=\"" << width << "\" offheight=\"" << height << "\" fovy=\"45\"/>\n"
        << "    <quality offsamples=\"0\" shadowsize=\"2048\"/>\n"
        << "    <map znear=\"0.005\" zfar=\"25\"/>\n"
        << "    <headlight ambient=\"0.25 0.25 0.25\" diffuse=\"0.35 0.35 0.35\" "
           "specular=\"0.05 0.05 0.05\"/>\n"
        << "  </visual>\n";
  }

  void write_defaults(std::ostringstream& xml) {
    // Contact bits: scene objects are type 1 / affinity 1, robot links type 2 / affinity 1, so
    // the robot touches the world but never itself; the head (class "head") touches nothing.
    xml << "  <default>\n"
        << "    <geom contype=\"1\" conaffinity=\"1\" condim=\"3\" friction=\"1 0.005 0.0001\" "
           "solref=\"0.004 1\"/>\n"
        << "    <joint damping=\"0\" armature=\"0\"/>\n"
        << "    <default class=\"arm\">\n"
        << "      <geom contype=\"2\" conaffinity=\"1\" group=\"" << kRobotGeomGroup
        << "\" material=\"robot_shell\"/>\n"
        // Reflected rotor inertia of a geared drive; it also keeps the small finger links stiff
        // enough for a 1 ms step.
        << "      <joint armature=\"0.02\" damping=\"0.05\" solreflimit=\"0.004 1\" "
           "solimplimit=\"0.99 0.999 0.001\"/>\n"
        << "    </default>\n"
        << "    <default class=\"head\">\n"
        << "      <geom contype=\"0\" conaffinity=\"0\" group=\"" << kHiddenFromEyesGeomGroup
        << "\" material=\"robot_shell\"/>\n"
        << "    </default>\n"
        << "  </default>\n";
  }

  void add_texture(std::ostringstream& assets, const std::string& name,
                   const config::TextureConfig& texture, const std::array<double, 3>& rgb,
                   bool tiled, double extent_m) {
    int size_px = 0;
    double feature_px = kTexelsPerFeature;
    if (tiled) {
      size_px = kTiledTexturePx;
    } else {
      // One cube face spans the object's largest extent.
      const double texels =
          texture.kind == TextureKind::kChessboard ? kTexelsPerChessboardSquare : kTexelsPerFeature;
      size_px = static_cast<int>(std::lround(extent_m / texture.feature_size_m * texels));
      size_px = std::clamp(size_px, kMinFacePx, kMaxFacePx);
      feature_px = size_px * texture.feature_size_m / extent_m;
    }
    assets << "    <texture name=\"" << xml_escape(name) << "\" type=\"" << (tiled ? "2d" : "cube")
           << "\" builtin=\"flat\" width=\"" << size_px << "\" height=\"" << size_px << "\" rgb1=\""
           << vec(rgb) << "\" rgb2=\"" << vec(rgb) << "\"/>\n";
    model_.textures.push_back({name, texture, rgb, feature_px});
  }

  void write_assets(std::ostringstream& xml) {
    std::ostringstream assets;
    assets << "    <texture name=\"sky\" type=\"skybox\" builtin=\"gradient\" width=\"256\" "
              "height=\"256\" rgb1=\""
           << vec(scene_.sky_rgb) << "\" rgb2=\"0.92 0.92 0.90\"/>\n";
    assets << "    <material name=\"robot_shell\" rgba=\"0.86 0.87 0.88 1\" specular=\"0.3\" "
              "shininess=\"0.4\"/>\n"
           << "    <material name=\"robot_joint\" rgba=\"0.22 0.24 0.27 1\" specular=\"0.2\"/>\n"
           << "    <material name=\"eye_sky\" rgba=\"" << rgba(scene_.sky_rgb)
           << "\" emission=\"0.4\" specular=\"0\" shininess=\"0\"/>\n"
           << "    <material name=\"eye_white\" rgba=\"0.95 0.95 0.93 1\" specular=\"0.5\"/>\n"
           << "    <material name=\"eye_lens\" rgba=\"0.05 0.05 0.07 1\" specular=\"0.8\" "
              "shininess=\"0.9\"/>\n";
    if (scene_.floor) {
      const double tile_m =
          kTiledTexturePx / kTexelsPerFeature * scene_.floor_texture.feature_size_m;
      if (scene_.floor_texture.kind != TextureKind::kNone) {
        add_texture(assets, "floor_texture", scene_.floor_texture, scene_.floor_rgb, true, 0.0);
        assets << "    <material name=\"floor\" texture=\"floor_texture\" texuniform=\"true\" "
                  "texrepeat=\""
               << num(1.0 / tile_m) << " " << num(1.0 / tile_m) << "\" reflectance=\"0\"/>\n";
      } else {
        assets << "    <material name=\"floor\" rgba=\"" << rgba(scene_.floor_rgb) << "\"/>\n";
      }
    }
    for (const auto& object : scene_.objects) {
      if (object.texture.kind == TextureKind::kNone) continue;
      const bool tiled = object.shape == ShapeKind::kPlane;
      const double extent = std::max({object.size_m[0], object.size_m[1], object.size_m[2]});
      const std::string texture_name = "texture_" + object.name;
      add_texture(assets, texture_name, object.texture, object.rgb, tiled, extent);
      assets << "    <material name=\"material_" << xml_escape(object.name) << "\" texture=\""
             << xml_escape(texture_name) << "\"";
      if (tiled) {
        const double tile_m = kTiledTexturePx / kTexelsPerFeature * object.texture.feature_size_m;
        assets << " texuniform=\"true\" texrepeat=\"" << num(1.0 / tile_m) << " "
               << num(1.0 / tile_m) << "\"";
      }
      assets << " specular=\"0.1\" shininess=\"0.2\"/>\n";
    }
    xml << "  <asset>\n" << assets.str() << "  </asset>\n";
  }

  void write_world(std::ostringstream& xml) {
    // Two soft directional lights (key and fill) plus MuJoCo's headlight; they cast shadows only
    // when a view turns shadows on (the overview does, the eyes do not by default).
    xml << "    <light name=\"key\" directional=\"true\" pos=\"1 -1 4\" dir=\"-0.3 0.35 -1\" "
           "diffuse=\"0.55 0.55 0.52\" specular=\"0.15 0.15 0.15\" castshadow=\"true\"/>\n"
        << "    <light name=\"fill\" directional=\"true\" pos=\"-1 1 4\" dir=\"0.5 -0.3 -1\" "
           "diffuse=\"0.25 0.25 0.27\" specular=\"0 0 0\" castshadow=\"false\"/>\n";
    if (scene_.floor) {
      // Drawn out to the sky planes (it collides as an infinite half-space regardless). The third
      // size is MuJoCo's rendering grid spacing: every light is directional, so the lighting is
      // the same across the plane and one quad per 25 m does; the 5 cm grid it had drew 200 x 200
      // quads per view, which cost llvmpipe more than the rest of the scene together.
      xml << "    <geom name=\"floor\" type=\"plane\" size=\"25 25 25\" material=\"floor\" "
             "group=\""
          << kSceneGeomGroup << "\"/>\n";
    }
    // The eyes' sky: five planes 25 m out, facing in; emission 0.4 plus the headlight (0.25
    // ambient, 0.35 diffuse) shows them in about the sky's colour. MuJoCo's skybox costs llvmpipe
    // about 10 ms per 640x480 frame (several times the rest of the scene), so only
    // third-person views draw it; they hide these planes (group kEyeSkyGeomGroup). One quad per
    // plane, as for the floor.
    struct SkyPlane {
      const char* name;
      Eigen::Vector3d position;
      Eigen::Matrix3d rotation;
    };
    const double d = 25.0;  // Corners (d sqrt 3 away) stay inside the 50 m far plane.
    const SkyPlane planes[] = {
        {"sky_front",
         {d, 0, 0},
         Eigen::AngleAxisd(-std::numbers::pi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix()},
        {"sky_back",
         {-d, 0, 0},
         Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix()},
        {"sky_left",
         {0, d, 0},
         Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix()},
        {"sky_right",
         {0, -d, 0},
         Eigen::AngleAxisd(-std::numbers::pi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix()},
        {"sky_top",
         {0, 0, d},
         Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitX()).toRotationMatrix()},
    };
    for (const auto& plane : planes) {
      xml << "    <geom name=\"" << plane.name << "\" type=\"plane\" size=\"" << num(d) << " "
          << num(d) << " " << num(d) << "\" pos=\"" << vec(plane.position) << "\" quat=\""
          << quat(plane.rotation)
          << "\" material=\"eye_sky\" contype=\"0\" conaffinity=\"0\" group=\"" << kEyeSkyGeomGroup
          << "\"/>\n";
    }
    write_pedestal(xml);
    for (const CameraConfig* camera : cameras_on("base")) write_camera(xml, *camera, "    ");
    const auto& overview = scene_.overview;
    const Eigen::Vector3d position(overview.xyz_m[0], overview.xyz_m[1], overview.xyz_m[2]);
    const Eigen::Vector3d target(overview.look_at_m[0], overview.look_at_m[1],
                                 overview.look_at_m[2]);
    Eigen::Vector3d forward = (target - position).normalized();
    Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ());
    if (right.norm() < 1e-6) right = Eigen::Vector3d::UnitY();  // Looking straight down.
    right.normalize();
    const Eigen::Vector3d up = right.cross(forward);
    xml << "    <camera name=\"" << kOverviewCameraName << "\" mode=\"fixed\" pos=\""
        << vec(position) << "\" xyaxes=\"" << vec(right) << " " << vec(up) << "\" fovy=\""
        << num(overview.fovy_rad * 180.0 / std::numbers::pi) << "\"/>\n";
  }

  // The robot's trunk: a column from the floor up to the lowest link hanging from the base and,
  // when links hang from the base side by side (shoulders), a torso between them.
  void write_pedestal(std::ostringstream& xml) {
    const auto it = children_.find("base");
    if (it == children_.end()) return;
    double z_min = 1e9, z_max = -1e9, y_max = 0.0;
    for (const JointConfig* joint : it->second) {
      z_min = std::min(z_min, joint->origin.xyz_m[2]);
      z_max = std::max(z_max, joint->origin.xyz_m[2]);
      y_max = std::max(y_max, std::abs(joint->origin.xyz_m[1]));
    }
    if (y_max > 0.1 && z_min > 0.4) {
      const double top = z_max - 0.03;
      const double bottom = z_min - 0.35;
      xml << "    <geom name=\"torso\" class=\"arm\" type=\"box\" pos=\"0 0 "
          << num((top + bottom) / 2) << "\" size=\"0.09 " << num(y_max - 0.06) << " "
          << num((top - bottom) / 2) << "\"/>\n";
      xml << "    <geom name=\"pedestal\" class=\"arm\" type=\"cylinder\" fromto=\"0 0 0 0 0 "
          << num(bottom) << "\" size=\"0.06\" material=\"robot_joint\"/>\n";
      xml << "    <geom name=\"pedestal_foot\" class=\"arm\" type=\"cylinder\" fromto=\"0 0 0 0 0 "
             "0.03\" size=\"0.25\" material=\"robot_joint\"/>\n";
    } else if (z_min > 0.02) {
      xml << "    <geom name=\"pedestal\" class=\"arm\" type=\"cylinder\" fromto=\"0 0 0 0 0 "
          << num(z_min - 0.02) << "\" size=\"0.04\" material=\"robot_joint\"/>\n";
    }
  }

  // Which cameras hang from a link.
  std::vector<const CameraConfig*> cameras_on(const std::string& link) const {
    std::vector<const CameraConfig*> found;
    for (const auto& camera : rig_.cameras) {
      if (camera.parent == link) found.push_back(&camera);
    }
    return found;
  }

  void write_link_children(std::ostringstream& xml, const std::string& parent, int depth) {
    const auto it = children_.find(parent);
    if (it == children_.end()) return;
    for (const JointConfig* joint : it->second) write_link(xml, *joint, depth);
  }

  void write_link(std::ostringstream& xml, const JointConfig& joint, int depth) {
    const std::string indent(static_cast<std::size_t>(depth) * 2, ' ');
    const bool head = carries_camera(rig_, joint.name);
    const std::string geom_class = head ? "head" : "arm";
    const Eigen::Matrix3d rotation = rotation_from_rpy(joint.origin.rpy_rad);
    xml << indent << "<body name=\"" << xml_escape(joint.name) << "\" pos=\""
        << vec(joint.origin.xyz_m) << "\" quat=\"" << quat(rotation) << "\" childclass=\""
        << geom_class << "\">\n";
    write_joint(xml, joint, joint.name, indent + "  ");
    write_link_geometry(xml, joint, indent + "  ");
    for (const CameraConfig* camera : cameras_on(joint.name))
      write_camera(xml, *camera, indent + "  ");
    write_link_children(xml, joint.name, depth + 1);
    xml << indent << "</body>\n";
    if (hands_.count(joint.name) != 0 && is_leaf(joint.name)) {
      // The gripper's second finger: a sibling body on the same axis whose joint the equality
      // constraint below holds at minus the gripper joint, so one rig joint opens both fingers.
      xml << indent << "<body name=\"" << xml_escape(joint.name + kMimicSuffix) << "\" pos=\""
          << vec(joint.origin.xyz_m) << "\" quat=\"" << quat(rotation) << "\" childclass=\""
          << geom_class << "\">\n";
      JointConfig mimic = joint;
      mimic.min_position_rad = -joint.max_position_rad;
      mimic.max_position_rad = -joint.min_position_rad;
      write_joint(xml, mimic, joint.name + kMimicSuffix, indent + "  ");
      write_finger(xml, *hands_.at(joint.name), -1.0, indent + "  ");
      xml << indent << "</body>\n";
      mimics_.push_back(joint.name);
    }
  }

  void write_joint(std::ostringstream& xml, const JointConfig& joint, const std::string& name,
                   const std::string& indent) {
    xml << indent << "<joint name=\"" << xml_escape(name) << "\" type=\"hinge\" axis=\""
        << vec(joint.axis) << "\" limited=\"true\" range=\"" << num(joint.min_position_rad) << " "
        << num(joint.max_position_rad) << "\"/>\n";
  }

  bool is_leaf(const std::string& link) const { return children_.count(link) == 0; }

  /// One finger: a beam from the gripper's axis to just short of the tip, and a pad whose front
  /// face's middle is the rig's fingertip (touch_sensors.<name>.fingertip_xy_m).
  void write_finger(std::ostringstream& xml, const config::TouchSensorConfig& hand, double side,
                    const std::string& indent) {
    const double beam_half_m =
        0.5 * (hand.fingertip_x_m - 2.0 * kFingerPadHalf_m + kFingerBeamOffset_m);
    xml << indent << "<geom type=\"box\" pos=\"" << num(beam_half_m) << " "
        << num(side * (hand.fingertip_y_m + kFingerBeamOffset_m)) << " 0\" size=\""
        << num(beam_half_m) << " 0.005 0.014\" material=\"robot_joint\"/>\n";
    xml << indent << "<geom type=\"box\" pos=\"" << num(hand.fingertip_x_m - kFingerPadHalf_m)
        << " " << num(side * hand.fingertip_y_m) << " 0\" size=\"" << num(kFingerPadHalf_m)
        << " 0.007 0.014\" material=\"robot_joint\"/>\n";
  }

  void write_link_geometry(std::ostringstream& xml, const JointConfig& joint,
                           const std::string& indent) {
    const auto it = children_.find(joint.name);
    const auto cameras = cameras_on(joint.name);
    bool drew = false;
    if (it != children_.end()) {
      for (const JointConfig* child : it->second) {
        const Eigen::Vector3d to(child->origin.xyz_m[0], child->origin.xyz_m[1],
                                 child->origin.xyz_m[2]);
        const double length = to.norm();
        if (length < 1e-6) continue;
        const double radius = std::clamp(0.12 * length, 0.018, 0.04);
        xml << indent << "<geom type=\"capsule\" fromto=\"0 0 0 " << vec(to) << "\" size=\""
            << num(radius) << "\"/>\n";
        if (hands_.count(child->name) != 0) {
          // The palm, where the gripper's fingers are mounted.
          xml << indent << "<geom type=\"box\" pos=\"" << vec(to - Eigen::Vector3d(0.008, 0, 0))
              << "\" size=\"0.012 0.03 0.02\" material=\"robot_joint\"/>\n";
        }
        drew = true;
      }
    }
    if (!cameras.empty()) {
      // An eyeball around the optical centre, with a dark lens on the optical axis.
      for (const CameraConfig* camera : cameras) {
        const Eigen::Vector3d centre(camera->mount.xyz_m[0], camera->mount.xyz_m[1],
                                     camera->mount.xyz_m[2]);
        const Eigen::Vector3d optical_axis =
            rotation_from_rpy(camera->mount.rpy_rad) * Eigen::Vector3d::UnitZ();
        xml << indent << "<geom type=\"sphere\" pos=\"" << vec(centre - 0.012 * optical_axis)
            << "\" size=\"0.024\" material=\"eye_white\"/>\n";
        xml << indent << "<geom type=\"cylinder\" fromto=\"" << vec(centre - 0.004 * optical_axis)
            << " " << vec(centre + 0.0125 * optical_axis)
            << "\" size=\"0.011\" material=\"eye_lens\"/>\n";
      }
      drew = true;
    }
    if (hands_.count(joint.name) != 0 && is_leaf(joint.name)) {
      write_finger(xml, *hands_.at(joint.name), 1.0, indent);
      drew = true;
    }
    if (!drew) {
      xml << indent << "<geom type=\"sphere\" size=\"0.02\" material=\"robot_joint\"/>\n";
    }
    // A dark collar marks the joint axis.
    const Eigen::Vector3d axis =
        Eigen::Vector3d(joint.axis[0], joint.axis[1], joint.axis[2]).normalized();
    if (cameras.empty()) {
      xml << indent << "<geom type=\"cylinder\" fromto=\"" << vec(-0.018 * axis) << " "
          << vec(0.018 * axis) << "\" size=\"" << (hands_.count(joint.name) ? "0.012" : "0.026")
          << "\" material=\"robot_joint\" contype=\"0\" conaffinity=\"0\"/>\n";
    }
  }

  void write_camera(std::ostringstream& xml, const CameraConfig& camera,
                    const std::string& indent) {
    // MuJoCo cameras look down their -z with y up; the rig's optical frame (OpenCV) looks down
    // +z with y down: the same frame turned half a turn about x.
    const Eigen::Matrix3d R_parent_optical = rotation_from_rpy(camera.mount.rpy_rad);
    const Eigen::Matrix3d R_parent_mujoco =
        R_parent_optical * Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
    const double fovy_deg =
        2.0 * std::atan(camera.height_px / (2.0 * camera.focal_y_px)) * 180.0 / std::numbers::pi;
    xml << indent << "<camera name=\"" << xml_escape(camera.name) << "\" pos=\""
        << vec(camera.mount.xyz_m) << "\" quat=\"" << quat(R_parent_mujoco) << "\" fovy=\""
        << num(fovy_deg) << "\"/>\n";
  }

  void write_objects(std::ostringstream& xml) {
    for (const auto& object : scene_.objects) write_object(xml, object);
  }

  void write_object(std::ostringstream& xml, const SceneObjectConfig& object) {
    const Eigen::Matrix3d rotation = rotation_from_rpy(object.pose.rpy_rad);
    xml << "    <body name=\"" << xml_escape(object.name) << "\" pos=\"" << vec(object.pose.xyz_m)
        << "\" quat=\"" << quat(rotation) << "\""
        << (object.body == config::BodyKind::kScripted ? " mocap=\"true\"" : "") << ">\n";
    if (object.body == config::BodyKind::kFree) {
      xml << "      <freejoint name=\"" << xml_escape(object.name) << "\"/>\n";
    }
    const auto& s = object.size_m;
    std::string type, size;
    switch (object.shape) {
      case ShapeKind::kSphere:
        type = "sphere";
        size = num(s[0] / 2);
        break;
      case ShapeKind::kBox:
        type = "box";
        size = num(s[0] / 2) + " " + num(s[1] / 2) + " " + num(s[2] / 2);
        break;
      case ShapeKind::kCylinder:
        type = "cylinder";
        size = num(s[0] / 2) + " " + num(s[2] / 2);
        break;
      case ShapeKind::kCapsule:
        type = "capsule";
        size = num(s[0] / 2) + " " + num(s[2] / 2);
        break;
      case ShapeKind::kPlane:
        type = "plane";
        size = num(s[0] / 2) + " " + num(s[1] / 2) + " 0.05";
        break;
    }
    xml << "      <geom name=\"" << xml_escape(object.name) << "\" type=\"" << type << "\" size=\""
        << size << "\" group=\"" << kSceneGeomGroup << "\" friction=\"" << num(object.friction)
        << " 0.005 0.0001\"";
    if (object.texture.kind != TextureKind::kNone) {
      xml << " material=\"material_" << xml_escape(object.name) << "\" rgba=\"1 1 1 1\"";
    } else {
      xml << " rgba=\"" << rgba(object.rgb) << "\"";
    }
    if (object.body == config::BodyKind::kFree) xml << " mass=\"" << num(object.mass_kg) << "\"";
    xml << "/>\n    </body>\n";
  }

  void write_equalities(std::ostringstream& xml) {
    if (mimics_.empty()) return;
    xml << "  <equality>\n";
    for (const auto& name : mimics_) {
      xml << "    <joint joint1=\"" << xml_escape(name + kMimicSuffix) << "\" joint2=\""
          << xml_escape(name) << "\" polycoef=\"0 -1 0 0 0\" solref=\"0.005 1\"/>\n";
    }
    xml << "  </equality>\n";
  }

  void write_actuators(std::ostringstream& xml) {
    // Joints that do not carry a camera are driven through physics by a torque motor; the
    // servo model closes the position loop (PD plus gravity feed-forward) in the physics step.
    std::ostringstream actuators;
    for (const auto& joint : rig_.joints) {
      if (carries_camera(rig_, joint.name)) continue;
      const double limit = joint.max_effort_nm > 0.0 ? joint.max_effort_nm : 1e6;
      actuators << "    <motor name=\"" << xml_escape(joint.name) << "\" joint=\""
                << xml_escape(joint.name) << "\" gear=\"1\" ctrllimited=\"true\" ctrlrange=\""
                << num(-limit) << " " << num(limit) << "\"/>\n";
    }
    if (!actuators.str().empty()) xml << "  <actuator>\n" << actuators.str() << "  </actuator>\n";
  }

  const RigConfig& rig_;
  const SceneConfig& scene_;
  const MjcfOptions& options_;
  std::map<std::string, std::vector<const JointConfig*>> children_;
  std::map<std::string, const config::TouchSensorConfig*> hands_;  // By parent (gripper) joint.
  std::vector<std::string> mimics_;
  GeneratedModel model_;
};

}  // namespace

bool carries_camera(const RigConfig& rig, const std::string& joint_name) {
  for (const auto& camera : rig.cameras) {
    // Walk from the camera's link to the base; the joints on the way carry it.
    std::string link = camera.parent;
    int guard = 0;
    while (link != "base" && guard++ < 1000) {
      if (link == joint_name) return true;
      const JointConfig* joint = rig.find_joint(link);
      if (joint == nullptr) break;
      link = joint->parent;
    }
  }
  return false;
}

void check_cameras_representable(const RigConfig& rig) {
  std::vector<config::ConfigIssue> issues;
  for (const auto& camera : rig.cameras) {
    const std::string path = "cameras." + camera.name;
    const double centre_x = (camera.width_px - 1) / 2.0;
    const double centre_y = (camera.height_px - 1) / 2.0;
    // What the sim cannot render matters for the cameras it serves; a real camera beside it (a
    // calibrated V4L2 eye) keeps its own principal point and distortion.
    const bool rendered = camera.backend == "sim";
    std::string why;
    if (rendered && !camera.distortion.is_zero() &&
        !SimLens::ideal_window(intrinsics_of(camera), camera.distortion, &why)) {
      issues.push_back({rig.source_file, 0, 0, path + ".distortion",
                        "the simulator cannot render this lens: " + why + " (k1 " +
                            num(camera.distortion.k1) + ", k2 " + num(camera.distortion.k2) +
                            ", p1 " + num(camera.distortion.p1) + ", p2 " +
                            num(camera.distortion.p2) + ", k3 " + num(camera.distortion.k3) + ")"});
    }
    if (rendered && (std::abs(camera.principal_x_px - centre_x) > 1e-3 ||
                     std::abs(camera.principal_y_px - centre_y) > 1e-3)) {
      issues.push_back({rig.source_file, 0, 0, path + ".principal_point_px",
                        "the simulator renders a centred principal point only: expected [" +
                            num(centre_x) + ", " + num(centre_y) + "] for " +
                            std::to_string(camera.width_px) + "x" +
                            std::to_string(camera.height_px) + ", found [" +
                            num(camera.principal_x_px) + ", " + num(camera.principal_y_px) + "]"});
    }
    if (rendered && std::abs(camera.focal_x_px - camera.focal_y_px) > 1e-9 * camera.focal_y_px) {
      issues.push_back({rig.source_file, 0, 0, path + ".focal_px",
                        "the simulator renders square pixels only: focal_x (" +
                            num(camera.focal_x_px) + ") must equal focal_y (" +
                            num(camera.focal_y_px) + ")"});
    }
    if (camera.parent != "base" && rig.find_joint(camera.parent) == nullptr) {
      issues.push_back({rig.source_file, 0, 0, path + ".parent",
                        "'" + camera.parent + "' is neither 'base' nor a joint"});
    }
    for (const auto& [key, side] :
         {std::pair{".width_px", camera.width_px}, std::pair{".height_px", camera.height_px}}) {
      if (side > kMaxCameraSidePx) {
        issues.push_back({rig.source_file, 0, 0, path + key,
                          "the simulator renders cameras of at most " +
                              std::to_string(kMaxCameraSidePx) + " px a side, found " +
                              std::to_string(side)});
      }
    }
    if (camera.name == kOverviewCameraName) {
      issues.push_back({rig.source_file, 0, 0, path,
                        std::string("'") + kOverviewCameraName +
                            "' is the name of the simulator's third-person camera; choose "
                            "another name"});
    }
  }
  if (!issues.empty()) throw config::ConfigError(std::move(issues));
}

void check_scene_representable(const RigConfig& rig, const SceneConfig& scene) {
  std::vector<config::ConfigIssue> issues;
  const auto issue = [&](std::string key_path, std::string message) {
    issues.push_back({scene.source_file, 0, 0, std::move(key_path), std::move(message)});
  };
  const auto moving = std::count_if(
      scene.objects.begin(), scene.objects.end(),
      [](const SceneObjectConfig& object) { return object.body != config::BodyKind::kStatic; });
  if (scene.objects.size() > static_cast<std::size_t>(kMaxSceneObjects)) {
    issue("objects", "the simulator holds at most " + std::to_string(kMaxSceneObjects) +
                         " objects (its collision broad phase grows with their square), found " +
                         std::to_string(scene.objects.size()));
  }
  if (moving > kMaxMovingObjects) {
    issue("objects", "the simulator moves at most " + std::to_string(kMaxMovingObjects) +
                         " free or scripted objects (MuJoCo's solver grows with the square of "
                         "their degrees of freedom and contacts), found " +
                         std::to_string(moving));
  }
  // The model names the robot's bodies and joints after the rig's joints, and a few geoms of its
  // own; an object of the same name would be a second element of that name.
  std::set<std::string> taken = {"world",    "floor",     "torso",    "pedestal",  "pedestal_foot",
                                 "sky_back", "sky_front", "sky_left", "sky_right", "sky_top"};
  for (const auto& joint : rig.joints) {
    taken.insert(joint.name);
    taken.insert(joint.name + kMimicSuffix);
  }
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const std::string& name = scene.objects[i].name;
    if (taken.count(name) != 0) {
      issue("objects[" + std::to_string(i) + "].name",
            "'" + name + "' is already the name of " +
                (rig.find_joint(name) != nullptr || name.ends_with(kMimicSuffix)
                     ? "a joint of rig " + rig.name
                     : std::string("a part of the simulated world")) +
                "; choose another name");
    }
  }
  const auto& overview = scene.overview;
  const Eigen::Vector3d position(overview.xyz_m[0], overview.xyz_m[1], overview.xyz_m[2]);
  const Eigen::Vector3d target(overview.look_at_m[0], overview.look_at_m[1], overview.look_at_m[2]);
  if (!((target - position).norm() > 1e-9)) {
    const auto point = [](const std::array<double, 3>& p) {
      return "[" + num(p[0]) + ", " + num(p[1]) + ", " + num(p[2]) + "]";
    };
    issue("overview_camera.look_at_m", "expected a point other than the camera's own position " +
                                           point(overview.xyz_m) + ", found " +
                                           point(overview.look_at_m));
  }
  if (!issues.empty()) throw config::ConfigError(std::move(issues));
}

GeneratedModel build_mjcf(const RigConfig& rig, const SceneConfig& scene,
                          const MjcfOptions& options) {
  check_cameras_representable(rig);
  check_scene_representable(rig, scene);
  return Builder(rig, scene, options).build();
}

}  // namespace cambio::sim
