#include "cambio/sim/world.hpp"

#include <array>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <vector>

#include <mujoco/mujoco.h>

#include "cambio/config/config_error.hpp"
#include "cambio/sim/mujoco_error.hpp"
#include "cambio/sim/procedural_texture.hpp"

namespace cambio::sim {

namespace {

constexpr const char* kModelFileName = "cambio_generated.xml";

// MuJoCo names the element it refused ("Object name = ball, id = 18, line = 137"). When the
// element was made from a scene object, the overview camera or a rig camera or joint, the input
// asked for something MuJoCo cannot build (a free object too light to have an inertia, say):
// that key is named. Otherwise the translation is at fault, and nullopt is returned.
std::optional<config::ConfigIssue> input_at_fault(const std::string& error,
                                                  const config::RigConfig& rig,
                                                  const config::SceneConfig& scene) {
  static constexpr std::string_view kName = "Object name = ";
  const std::size_t at = error.find(kName);
  if (at == std::string::npos) return std::nullopt;
  const std::size_t start = at + kName.size();
  const std::string name = error.substr(start, error.find_first_of(",\n", start) - start);
  std::string what = error.substr(0, error.find('\n'));
  if (what.starts_with("Error: ")) what.erase(0, 7);
  what = "MuJoCo cannot build it: " + what;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const std::string& object = scene.objects[i].name;
    if (name == object || name == "texture_" + object || name == "material_" + object) {
      return config::ConfigIssue{scene.source_file, 0, 0, "objects[" + std::to_string(i) + "]",
                                 what};
    }
  }
  if (name == kOverviewCameraName) {
    return config::ConfigIssue{scene.source_file, 0, 0, "overview_camera", what};
  }
  if (rig.find_camera(name) != nullptr) {
    return config::ConfigIssue{rig.source_file, 0, 0, "cameras." + name, what};
  }
  for (const auto& joint : rig.joints) {
    if (name == joint.name || name == joint.name + kMimicSuffix) {
      return config::ConfigIssue{rig.source_file, 0, 0, "joints." + joint.name, what};
    }
  }
  return std::nullopt;
}

// Compiles MJCF text through a virtual file system (nothing touches the disk).
mjModel* compile(const std::string& xml, const config::RigConfig& rig,
                 const config::SceneConfig& scene) {
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), kModelFileName, static_cast<int>(xml.size())) != 0) {
    throw MujocoError("MuJoCo: could not allocate the generated model in the virtual file system");
  }
  const int file = mj_findFileVFS(vfs.get(), kModelFileName);
  std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs->filedata[file]));
  std::array<char, 1024> error{};
  mjModel* model = nullptr;
  try {
    model = mj_loadXML(kModelFileName, vfs.get(), error.data(), static_cast<int>(error.size()));
  } catch (...) {
    mj_deleteVFS(vfs.get());
    throw;
  }
  mj_deleteVFS(vfs.get());
  if (model == nullptr) {
    if (auto issue = input_at_fault(error.data(), rig, scene)) {
      throw config::ConfigError({std::move(*issue)});
    }
    throw MujocoError(std::string("the generated MJCF does not compile: ") + error.data() +
                      " (a bug in the rig/scene to MJCF translation; run `cambio render --mjcf "
                      "FILE` to inspect it)");
  }
  return model;
}

}  // namespace

World::World(const config::RigConfig& rig, const config::SceneConfig& scene,
             const MjcfOptions& options)
    : rig_(rig), scene_(scene) {
  install_mujoco_handlers();
  GeneratedModel generated = build_mjcf(rig_, scene_, options);
  mjcf_ = std::move(generated.xml);
  model_ = compile(mjcf_, rig_, scene_);
  try {
    for (const auto& spec : generated.textures) {
      const int id = mj_name2id(model_, mjOBJ_TEXTURE, spec.texture_name.c_str());
      if (id < 0) throw MujocoError("generated texture '" + spec.texture_name + "' is missing");
      const int width = model_->tex_width[id];
      const int height = model_->tex_height[id];
      std::span<std::uint8_t> texels(model_->tex_rgb + model_->tex_adr[id],
                                     static_cast<std::size_t>(width) * height * 3);
      fill_procedural_texture(spec.texture, spec.rgb, spec.feature_px, width, height, texels);
    }
    data_ = mj_makeData(model_);
    if (data_ == nullptr) throw MujocoError("MuJoCo: could not allocate mjData");

    for (const auto& joint : rig_.joints) {
      JointIndex index;
      index.name = joint.name;
      index.joint_id = mj_name2id(model_, mjOBJ_JOINT, joint.name.c_str());
      index.qpos_address = model_->jnt_qposadr[index.joint_id];
      index.dof_address = model_->jnt_dofadr[index.joint_id];
      index.actuator_id = mj_name2id(model_, mjOBJ_ACTUATOR, joint.name.c_str());
      index.kinematic = index.actuator_id < 0;
      joints_.push_back(index);
    }
    for (const auto& object : scene_.objects) {
      ObjectIndex index;
      index.name = object.name;
      index.config = &object;
      index.body_id = mj_name2id(model_, mjOBJ_BODY, object.name.c_str());
      index.mocap_id = model_->body_mocapid[index.body_id];
      if (object.body == config::BodyKind::kFree) {
        index.qpos_address = model_->jnt_qposadr[model_->body_jntadr[index.body_id]];
      }
      objects_.push_back(index);
    }
    reset();
  } catch (...) {
    if (data_ != nullptr) mj_deleteData(data_);
    mj_deleteModel(model_);
    throw;
  }
}

World::~World() {
  mj_deleteData(data_);
  mj_deleteModel(model_);
}

int World::find_joint(std::string_view joint_name) const {
  for (std::size_t i = 0; i < joints_.size(); ++i) {
    if (joints_[i].name == joint_name) return static_cast<int>(i);
  }
  return -1;
}

int World::camera_id(const std::string& camera_name) const {
  const int id = mj_name2id(model_, mjOBJ_CAMERA, camera_name.c_str());
  if (id < 0) throw std::out_of_range("no camera named '" + camera_name + "' in the sim world");
  return id;
}

std::vector<int> World::end_effector_bodies(const std::string& link_name) const {
  const int link = mj_name2id(model_, mjOBJ_BODY, link_name.c_str());
  if (link < 0) throw std::out_of_range("no link named '" + link_name + "' in the sim world");
  std::vector<int> bodies{link};
  const int mimic = mj_name2id(model_, mjOBJ_BODY, (link_name + kMimicSuffix).c_str());
  if (mimic >= 0) bodies.push_back(mimic);
  const int parent = model_->body_parentid[link];
  if (parent > 0) bodies.push_back(parent);
  return bodies;
}

void World::reset() {
  mj_resetData(model_, data_);
  for (std::size_t i = 0; i < joints_.size(); ++i) {
    data_->qpos[joints_[i].qpos_address] = rig_.joints[i].initial_position_rad;
    const int mimic = mj_name2id(model_, mjOBJ_JOINT, (joints_[i].name + kMimicSuffix).c_str());
    if (mimic >= 0) data_->qpos[model_->jnt_qposadr[mimic]] = -rig_.joints[i].initial_position_rad;
  }
  // mj_resetData already put free and mocap bodies at their MJCF poses (the scene's).
  mj_forward(model_, data_);
}

double World::timestep_s() const {
  return model_->opt.timestep;
}

}  // namespace cambio::sim
