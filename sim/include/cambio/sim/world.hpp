#pragma once

#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/config/rig_config.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/sim/mjcf_builder.hpp"

struct mjModel_;
struct mjData_;

namespace cambio::sim {

/// Where a rig joint lives in the MuJoCo model.
struct JointIndex {
  std::string name;
  int joint_id = -1;
  int qpos_address = -1;
  int dof_address = -1;
  int actuator_id = -1;  ///< -1 for joints driven kinematically (they carry a camera).
  bool kinematic = false;
};

/// Where a scene object lives in the model.
struct ObjectIndex {
  std::string name;
  int body_id = -1;
  int mocap_id = -1;      ///< >= 0 for scripted objects.
  int qpos_address = -1;  ///< >= 0 for free objects (7 numbers: position, quaternion).
  const config::SceneObjectConfig* config = nullptr;
};

/// The MuJoCo world: the model generated from a rig and a scene, and the true state (mjData).
/// Built at configure time (allocates, may throw ConfigError or MujocoError); owns both.
/// Not thread-safe: the physics loop is its only writer.
class World {
 public:
  World(const config::RigConfig& rig, const config::SceneConfig& scene,
        const MjcfOptions& options = {});
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  const mjModel_* model() const { return model_; }
  mjModel_* model() { return model_; }
  const mjData_* data() const { return data_; }
  mjData_* data() { return data_; }

  const config::RigConfig& rig() const { return rig_; }
  const config::SceneConfig& scene() const { return scene_; }
  /// The generated MJCF (for debugging: `cambio render --mjcf`).
  const std::string& mjcf() const { return mjcf_; }

  /// In rig order (rig().joints).
  const std::vector<JointIndex>& joints() const { return joints_; }
  const std::vector<ObjectIndex>& objects() const { return objects_; }
  /// Index into joints(), or -1. No allocation.
  int find_joint(std::string_view joint_name) const;
  /// MuJoCo camera id of a rig camera or the overview; throws std::out_of_range if unknown.
  int camera_id(const std::string& camera_name) const;
  /// MuJoCo body ids of a touch sensor's end effector: its link, the generated mirrored finger
  /// and the link it hangs from (the palm). Throws std::out_of_range for an unknown link.
  std::vector<int> end_effector_bodies(const std::string& link_name) const;

  /// Puts every joint at its rig initial position and every object at its scene pose, at rest,
  /// time 0, then runs forward kinematics.
  void reset();
  double timestep_s() const;

 private:
  config::RigConfig rig_;
  config::SceneConfig scene_;
  std::string mjcf_;
  mjModel_* model_ = nullptr;
  mjData_* data_ = nullptr;
  std::vector<JointIndex> joints_;
  std::vector<ObjectIndex> objects_;
};

}  // namespace cambio::sim
