#include "cambio/control/kinematics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cambio::control {

namespace {

// Rig descriptions come from YAML (degrees turned into radians, axes normalised): rounding stays
// far below this, while a hand-typed rotation or axis that is plainly wrong is caught.
constexpr double kUnitTolerance = 1e-9;

bool is_rotation(const Eigen::Matrix3d& R) {
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < kUnitTolerance &&
         std::abs(R.determinant() - 1.0) < kUnitTolerance;
}

std::string quoted_list(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "'" : ", '") + name + "'";
  return text;
}

}  // namespace

Kinematics::Kinematics(const hal::HardwareInfo& hardware,
                       std::span<const FixedFrameInfo> fixed_frames) {
  const std::string where = "kinematics of '" + hardware.name + "': ";
  add_frame(where, std::string(kBase), 0, Eigen::Isometry3d::Identity());

  const auto& joints = hardware.joints;
  // Where each joint sits in the list, so that a parent listed after its child can be told
  // apart from an unknown one, and a cycle named.
  auto list_index = [&joints](std::string_view name) {
    for (std::size_t i = 0; i < joints.size(); ++i) {
      if (joints[i].name == name) return static_cast<int>(i);
    }
    return -1;
  };
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const hal::JointInfo& joint = joints[i];
    if (joint.parent != kBase) {
      const int parent = list_index(joint.parent);
      if (parent < 0) {
        throw std::invalid_argument(where + "joint '" + joint.name + "' hangs from '" +
                                    joint.parent + "', which is neither 'base' nor a joint");
      }
      if (parent >= static_cast<int>(i)) {
        // Walk up from the joint: back to itself is a cycle; reaching base is only disorder.
        std::string chain = "'" + joint.name + "'";
        int at = parent;
        for (std::size_t steps = 0; at >= 0 && steps <= joints.size(); ++steps) {
          chain += " -> '" + joints[static_cast<std::size_t>(at)].name + "'";
          if (at == static_cast<int>(i)) {
            throw std::invalid_argument(where + "the joints form a cycle: " + chain);
          }
          const std::string& next = joints[static_cast<std::size_t>(at)].parent;
          at = next == kBase ? -1 : list_index(next);
        }
        if (at >= 0) {
          throw std::invalid_argument(where + "the parent chain of joint '" + joint.name +
                                      "' never reaches base: " + chain + " ...");
        }
        throw std::invalid_argument(where + "joint '" + joint.name + "' comes before its parent '" +
                                    joint.parent + "' (HardwareInfo lists parents first)");
      }
    }
    if (std::abs(joint.axis_J.norm() - 1.0) > kUnitTolerance) {
      throw std::invalid_argument(where + "joint '" + joint.name + "' has a non-unit axis");
    }
    if (!is_rotation(joint.X_PJ.linear())) {
      throw std::invalid_argument(where + "joint '" + joint.name + "': X_PJ is not a rotation");
    }
    // Link frames follow the joint list, after base: the parent's is its list index + 1.
    const int parent_link = joint.parent == kBase ? 0 : list_index(joint.parent) + 1;
    joints_.push_back({joint.name, parent_link, joint.X_PJ, joint.axis_J});
    add_frame(where, joint.name, static_cast<int>(i) + 1, Eigen::Isometry3d::Identity());
  }

  const int link_count = joint_count() + 1;
  for (const hal::CameraInfo& camera : hardware.cameras) {
    const int link = find_frame(camera.parent_frame);
    if (link < 0 || link >= link_count) {
      throw std::invalid_argument(where + "camera '" + camera.name + "' is mounted on '" +
                                  camera.parent_frame + "', which is neither 'base' nor a joint");
    }
    if (!is_rotation(camera.X_PC.linear())) {
      throw std::invalid_argument(where + "camera '" + camera.name + "': X_PC is not a rotation");
    }
    add_frame(where, camera.name, link, camera.X_PC);
  }
  for (const FixedFrameInfo& fixed : fixed_frames) {
    const int parent = find_frame(fixed.parent);
    if (parent < 0) {
      throw std::invalid_argument(where + "frame '" + fixed.name + "' hangs from '" + fixed.parent +
                                  "', which is not 'base', a joint, a camera or an earlier frame");
    }
    if (!is_rotation(fixed.X_PF.linear())) {
      throw std::invalid_argument(where + "frame '" + fixed.name + "': X_PF is not a rotation");
    }
    const Frame& parent_frame = frames_[static_cast<std::size_t>(parent)];
    add_frame(where, fixed.name, parent_frame.link, parent_frame.X_LF * fixed.X_PF);
  }

  std::vector<bool> grouped(joints_.size(), false);
  for (const hal::JointGroupInfo& group : hardware.groups) {
    for (const std::string& name : group.joints) {
      const int joint = find_joint(name);
      if (joint < 0) {
        throw std::invalid_argument(where + "group '" + group.name + "' names unknown joint '" +
                                    name + "'");
      }
      if (grouped[static_cast<std::size_t>(joint)]) {
        throw std::invalid_argument(where + "joint '" + name +
                                    "' is listed twice in the groups (again in '" + group.name +
                                    "')");
      }
      grouped[static_cast<std::size_t>(joint)] = true;
      rig_to_tree_.push_back(joint);
    }
  }

  q_.assign(joints_.size(), 0.0);
  q_scratch_.assign(joints_.size(), 0.0);
  X_WF_.assign(frames_.size(), Eigen::Isometry3d::Identity());
  place_frames();
}

void Kinematics::add_frame(const std::string& where, std::string name, int link,
                           const Eigen::Isometry3d& X_LF) {
  if (name.empty()) throw std::invalid_argument(where + "a frame has an empty name");
  if (find_frame(name) >= 0) {
    throw std::invalid_argument(where + "two frames are named '" + name +
                                "' (links, cameras and fixed frames share one namespace)");
  }
  frames_.push_back({std::move(name), link, X_LF});
}

int Kinematics::find_joint(std::string_view joint_name) const {
  for (std::size_t i = 0; i < joints_.size(); ++i) {
    if (joints_[i].name == joint_name) return static_cast<int>(i);
  }
  return -1;
}

int Kinematics::joint_index(std::string_view joint_name) const {
  const int joint = find_joint(joint_name);
  if (joint >= 0) return joint;
  std::vector<std::string> names;
  for (const Joint& j : joints_) names.push_back(j.name);
  throw std::out_of_range("kinematics: no joint named '" + std::string(joint_name) +
                          "'; the joints are " + quoted_list(names));
}

int Kinematics::find_frame(std::string_view frame_name) const {
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    if (frames_[i].name == frame_name) return static_cast<int>(i);
  }
  return -1;
}

int Kinematics::frame_index(std::string_view frame_name) const {
  const int frame = find_frame(frame_name);
  if (frame >= 0) return frame;
  std::vector<std::string> names;
  for (const Frame& f : frames_) names.push_back(f.name);
  throw std::out_of_range("kinematics: no frame named '" + std::string(frame_name) +
                          "'; the frames are " + quoted_list(names));
}

hal::Status Kinematics::update(std::span<const double> q_rad) noexcept {
  if (q_rad.size() != q_.size()) return hal::Status::kRejected;
  if (!std::all_of(q_rad.begin(), q_rad.end(), [](double q) { return std::isfinite(q); })) {
    return hal::Status::kRejected;
  }
  std::copy(q_rad.begin(), q_rad.end(), q_.begin());
  place_frames();
  return hal::Status::kOk;
}

hal::Status Kinematics::update_rig_order(std::span<const double> q_rig_rad) noexcept {
  if (q_rig_rad.size() != rig_to_tree_.size()) return hal::Status::kRejected;
  std::fill(q_scratch_.begin(), q_scratch_.end(), 0.0);
  for (std::size_t i = 0; i < rig_to_tree_.size(); ++i) {
    q_scratch_[static_cast<std::size_t>(rig_to_tree_[i])] = q_rig_rad[i];
  }
  return update(q_scratch_);
}

void Kinematics::place_frames() noexcept {
  // Parents first, so each link's parent is placed before it.
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    const Joint& joint = joints_[j];
    X_WF_[j + 1] = X_WF_[static_cast<std::size_t>(joint.parent_link)] * joint.X_PJ *
                   Eigen::AngleAxisd(q_[j], joint.axis_J);
  }
  for (std::size_t f = joints_.size() + 1; f < frames_.size(); ++f) {
    X_WF_[f] = X_WF_[static_cast<std::size_t>(frames_[f].link)] * frames_[f].X_LF;
  }
}

hal::Status Kinematics::jacobian_W(int frame, Eigen::Ref<Jacobian> J_W) const noexcept {
  return fill_jacobian(frame, Eigen::Matrix3d::Identity(), J_W);
}

hal::Status Kinematics::jacobian_F(int frame, Eigen::Ref<Jacobian> J_F) const noexcept {
  if (frame < 0 || frame >= frame_count()) return hal::Status::kRejected;
  return fill_jacobian(frame, X_WF_[static_cast<std::size_t>(frame)].linear().transpose(), J_F);
}

hal::Status Kinematics::fill_jacobian(int frame, const Eigen::Matrix3d& R_EW,
                                      Eigen::Ref<Jacobian> J_E) const noexcept {
  if (frame < 0 || frame >= frame_count() || J_E.cols() != joint_count()) {
    return hal::Status::kRejected;
  }
  J_E.setZero();
  const std::size_t f = static_cast<std::size_t>(frame);
  const Eigen::Vector3d p_WF = X_WF_[f].translation();
  // Walk from the frame's link to the base: each joint on the way turns F's origin about its
  // axis through the link origin (the link frame is the joint frame turned about that axis, so
  // the axis has the same coordinates in both): w = a_W, v = a_W x (p_WF - p_WL).
  for (int link = frames_[f].link; link != 0;) {
    const std::size_t j = static_cast<std::size_t>(link - 1);
    const Eigen::Isometry3d& X_WL = X_WF_[static_cast<std::size_t>(link)];
    const Eigen::Vector3d axis_W = X_WL.linear() * joints_[j].axis_J;
    J_E.col(static_cast<Eigen::Index>(j)).head<3>() =
        R_EW * axis_W.cross(p_WF - X_WL.translation());
    J_E.col(static_cast<Eigen::Index>(j)).tail<3>() = R_EW * axis_W;
    link = joints_[j].parent_link;
  }
  return hal::Status::kOk;
}

}  // namespace cambio::control
