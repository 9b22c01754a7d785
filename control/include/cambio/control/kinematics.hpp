#pragma once

#include <cassert>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cambio/hal/hardware_info.hpp"
#include "cambio/hal/status.hpp"

namespace cambio::control {

/// A frame rigidly attached to another frame of the tree (a gripper tip, a tool centre point, a
/// marker): given when the kinematics is constructed, placed by every update().
struct FixedFrameInfo {
  std::string name;  ///< Unique among all frames (links, cameras, fixed frames).
  /// A link ("base" or a joint's name), a camera, or a fixed frame listed before this one.
  std::string parent;
  Eigen::Isometry3d X_PF = Eigen::Isometry3d::Identity();  ///< This frame in its parent (m).
};

/// Geometric Jacobian of a frame's origin, 6 x joint_count(): rows 0-2 the linear velocity of the
/// origin (m/s per rad/s), rows 3-5 the angular velocity (rad/s per rad/s), i.e. a twist [v; w],
/// linear first, as ViSP's velocity twists (vpColVector v_c = [vx vy vz wx wy wz]).
using Jacobian = Eigen::Matrix<double, 6, Eigen::Dynamic>;

/// Forward kinematics and geometric Jacobians of every frame of a rig's joint tree: links,
/// cameras and fixed frames added at construction.
///
/// Frames and conventions:
///  - The world frame W is the robot's base: the sim puts "base" at the world origin (the rig's
///    root links are children of MuJoCo's worldbody, with no offset), and a real robot's world is
///    its base by definition. x forward, y left, z up with every joint at zero (the rig file's
///    convention).
///  - Every joint is revolute and moves the link named after it: X_PL(q) = X_PJ * Rot(axis_J, q),
///    positive q turning right-handed about axis_J (hal::JointInfo), so a link's origin lies on
///    its joint's axis and the link frame is the joint frame at q = 0.
///  - A camera's frame is its optical frame (OpenCV: z forward, x right, y down):
///    X_WC = X_WP * X_PC (hal::CameraInfo).
///  - Joint positions are in the HardwareInfo's joint order (parents first), in rad; see
///    joint_index() and update_rig_order() for the rig order (the groups' joints concatenated,
///    what the joint loop publishes).
///  - Jacobians are [v; w], linear first (Jacobian). jacobian_W() expresses both halves in W;
///    jacobian_F() in the frame F itself, which for a camera is what ViSP's interaction matrix
///    takes: s_dot = L_s * J_C * q_dot. Only the joints that are ancestors of a frame have
///    non-zero columns.
///
/// Lifecycle: the constructor validates and allocates (configure time, may throw), and so do the
/// name lookups that throw (joint_index(), frame_index(): resolve names once, at configure time);
/// update(), update_rig_order(), X_WF() and the Jacobians neither allocate nor throw (real-time
/// safe). Not thread-safe: one thread updates and queries (give each loop its own instance).
class Kinematics {
 public:
  /// Name of the root link, fixed in the world.
  static constexpr std::string_view kBase = "base";

  /// Builds the tree from `hardware`'s joints and cameras and adds `fixed_frames` (in order).
  /// Throws std::invalid_argument, naming the offender, for: a duplicate or empty frame name, a
  /// parent that is neither "base" nor a joint (or, for a fixed frame, an earlier frame), a
  /// parent chain that forms a cycle or lists a child before its parent, a non-unit axis, a
  /// rotation that is not orthonormal, a group naming an unknown joint or a joint twice.
  explicit Kinematics(const hal::HardwareInfo& hardware,
                      std::span<const FixedFrameInfo> fixed_frames = {});

  int joint_count() const { return static_cast<int>(joints_.size()); }
  /// Links (base first, then one per joint), then cameras, then fixed frames.
  int frame_count() const { return static_cast<int>(frames_.size()); }

  /// Index of a joint in the position vector (HardwareInfo order); -1 if there is none.
  int find_joint(std::string_view joint_name) const;
  /// As find_joint(); throws std::out_of_range listing the joints if there is none.
  int joint_index(std::string_view joint_name) const;
  /// Throws std::out_of_range for an index outside [0, joint_count()).
  const std::string& joint_name(int joint) const { return joints_.at(joint).name; }

  /// Index of a frame (a link: "base" or a joint's name; a camera; a fixed frame); -1 if none.
  int find_frame(std::string_view frame_name) const;
  /// As find_frame(); throws std::out_of_range listing the frames if there is none.
  int frame_index(std::string_view frame_name) const;
  /// Throws std::out_of_range for an index outside [0, frame_count()).
  const std::string& frame_name(int frame) const { return frames_.at(frame).name; }
  /// The frame of the link a joint moves.
  static int link_frame(int joint) { return joint + 1; }

  /// Joints in rig order (the groups' joints concatenated), the order of JointStateFrame and
  /// JointTargetFrame. rig_to_tree()[i] is the joint index of the rig's i-th joint.
  int rig_joint_count() const { return static_cast<int>(rig_to_tree_.size()); }
  std::span<const int> rig_to_tree() const { return rig_to_tree_; }

  /// Places every frame for joint positions `q_rad` (size joint_count(), HardwareInfo order, any
  /// finite value: limits are the joint loop's business). kRejected, leaving the poses as they
  /// were, for a wrong size or a non-finite position. Real-time safe: no allocation.
  [[nodiscard]] hal::Status update(std::span<const double> q_rad) noexcept;
  /// As above. Pass a contiguous vector: Eigen copies any other expression into a temporary,
  /// which allocates.
  [[nodiscard]] hal::Status update(const Eigen::Ref<const Eigen::VectorXd>& q_rad) noexcept {
    return update(std::span<const double>(q_rad.data(), static_cast<std::size_t>(q_rad.size())));
  }
  /// As update(), from positions in rig order (size rig_joint_count()). Joints that no group
  /// lists (only in hand-built descriptions) are placed at 0 rad. Real-time safe.
  [[nodiscard]] hal::Status update_rig_order(std::span<const double> q_rig_rad) noexcept;

  /// The positions of the last accepted update (HardwareInfo order, rad); zeros before any.
  std::span<const double> q_rad() const { return q_; }

  /// Pose of frame F in the world (the base) at the last update(), in metres. Every frame is at
  /// its zero-position pose before the first update().
  /// @pre 0 <= frame < frame_count(). Real-time safe.
  const Eigen::Isometry3d& X_WF(int frame) const noexcept {
    assert(frame >= 0 && frame < frame_count());
    return X_WF_[static_cast<std::size_t>(frame)];
  }

  /// Geometric Jacobian of frame F's origin at the last update(), expressed in W:
  /// [v_W; w_W] = J_W * q_dot. `J_W` must be 6 x joint_count(); kRejected (untouched) for a wrong
  /// size or frame index. Real-time safe.
  [[nodiscard]] hal::Status jacobian_W(int frame, Eigen::Ref<Jacobian> J_W) const noexcept;

  /// The same Jacobian expressed in F: [v_F; w_F] = J_F * q_dot with v_F = R_FW v_W and
  /// w_F = R_FW w_W (for a camera, the velocity twist ViSP's interaction matrices take).
  /// `J_F` must be 6 x joint_count(); kRejected otherwise. Real-time safe.
  [[nodiscard]] hal::Status jacobian_F(int frame, Eigen::Ref<Jacobian> J_F) const noexcept;

  /// A zero Jacobian of the right size, to preallocate at configure time (allocates).
  Jacobian make_jacobian() const { return Jacobian::Zero(6, joint_count()); }

 private:
  struct Joint {
    std::string name;
    int parent_link = 0;  ///< Index into the link frames (0 = base).
    Eigen::Isometry3d X_PJ = Eigen::Isometry3d::Identity();
    Eigen::Vector3d axis_J = Eigen::Vector3d::UnitZ();
  };
  /// A frame as a fixed pose in a link: links are at the identity in themselves.
  struct Frame {
    std::string name;
    int link = 0;
    Eigen::Isometry3d X_LF = Eigen::Isometry3d::Identity();
  };

  void add_frame(const std::string& where, std::string name, int link,
                 const Eigen::Isometry3d& X_LF);
  void place_frames() noexcept;
  /// The Jacobian of `frame` with both halves expressed in E (R_EW maps W coordinates to E).
  hal::Status fill_jacobian(int frame, const Eigen::Matrix3d& R_EW,
                            Eigen::Ref<Jacobian> J_E) const noexcept;

  std::vector<Joint> joints_;
  std::vector<Frame> frames_;
  std::vector<int> rig_to_tree_;
  // Changing state, sized at construction.
  std::vector<double> q_;
  std::vector<double> q_scratch_;
  std::vector<Eigen::Isometry3d> X_WF_;
};

}  // namespace cambio::control
