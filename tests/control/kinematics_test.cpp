#include "cambio/control/kinematics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cambio/runtime/allocation_counter.hpp"

namespace cambio::control {
namespace {

/// A group of the sim backend with no limits (kinematics reads only names and joint order).
hal::JointGroupInfo sim_group(std::string name, std::vector<std::string> joints) {
  hal::JointGroupInfo group;
  group.name = std::move(name);
  group.backend = "sim";
  group.joints = std::move(joints);
  return group;
}

using std::numbers::pi;

constexpr double kL1M = 0.30;  // Planar arm: upper arm length.
constexpr double kL2M = 0.25;  // Planar arm: forearm length (to the tip frame).

Eigen::Isometry3d translation(double x, double y, double z) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(x, y, z);
  return X;
}

hal::JointInfo joint(const std::string& name, const std::string& parent,
                     const Eigen::Isometry3d& X_PJ, const Eigen::Vector3d& axis_J,
                     double min_rad = -pi, double max_rad = pi) {
  hal::JointInfo info;
  info.name = name;
  info.group = "arm";
  info.parent = parent;
  info.X_PJ = X_PJ;
  info.axis_J = axis_J;
  info.limits.min_position_rad = min_rad;
  info.limits.max_position_rad = max_rad;
  return info;
}

// The optical frame of a camera that looks along its link's x (z_C = x_L, x_C = -y_L,
// y_C = -z_L): the shipped rig's eye mount, rpy (-90, 0, -90) deg.
Eigen::Matrix3d R_LC_looking_forward() {
  Eigen::Matrix3d R;
  R.col(0) = -Eigen::Vector3d::UnitY();
  R.col(1) = -Eigen::Vector3d::UnitZ();
  R.col(2) = Eigen::Vector3d::UnitX();
  return R;
}

// Two links turning about z in the base's xy plane, a tip frame at the end of the forearm and a
// camera on the forearm's end looking along it.
hal::HardwareInfo planar_arm() {
  hal::HardwareInfo hardware;
  hardware.name = "planar";
  hardware.joints = {joint("shoulder", "base", Eigen::Isometry3d::Identity(), {0, 0, 1}),
                     joint("elbow", "shoulder", translation(kL1M, 0, 0), {0, 0, 1})};
  hardware.groups = {sim_group("arm", {"shoulder", "elbow"})};
  hal::CameraInfo camera;
  camera.name = "hand_eye";
  camera.parent_frame = "elbow";
  camera.X_PC = translation(kL2M, 0, 0);
  camera.X_PC.linear() = R_LC_looking_forward();
  hardware.cameras = {camera};
  return hardware;
}

const std::vector<FixedFrameInfo> kPlanarTip = {{"tip", "elbow", translation(kL2M, 0, 0)}};

Eigen::Isometry3d random_pose(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> offset_m(-0.3, 0.3);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() =
      Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized().matrix();
  X.translation() = Eigen::Vector3d(offset_m(rng), offset_m(rng), offset_m(rng));
  return X;
}

// A branching tree with arbitrary joint frames and axes, in no group order in particular:
//   base - a - b - c - cam (camera), tool (fixed, on the camera), tcp (fixed, on tool)
//              \- d - e
//   base - f
hal::HardwareInfo random_tree(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  auto axis = [&] {
    return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized().eval();
  };
  hal::HardwareInfo hardware;
  hardware.name = "tree";
  hardware.joints = {joint("a", "base", random_pose(rng), axis(), -2.0, 2.0),
                     joint("f", "base", random_pose(rng), axis(), -1.0, 1.5),
                     joint("b", "a", random_pose(rng), axis(), -2.5, 0.5),
                     joint("d", "a", random_pose(rng), axis(), 0.0, 2.0),
                     joint("c", "b", random_pose(rng), axis(), -1.0, 1.0),
                     joint("e", "d", random_pose(rng), axis(), -3.0, 3.0)};
  hardware.groups = {sim_group("second", {"e", "d", "f"}), sim_group("first", {"c", "a", "b"})};
  hal::CameraInfo camera;
  camera.name = "cam";
  camera.parent_frame = "c";
  camera.X_PC = random_pose(rng);
  hardware.cameras = {camera};
  return hardware;
}

std::vector<FixedFrameInfo> random_tree_frames(std::mt19937& rng) {
  return {{"tool", "cam", random_pose(rng)}, {"tcp", "tool", random_pose(rng)}};
}

Eigen::VectorXd random_configuration(const hal::HardwareInfo& hardware, std::mt19937& rng) {
  Eigen::VectorXd q(static_cast<Eigen::Index>(hardware.joints.size()));
  for (std::size_t j = 0; j < hardware.joints.size(); ++j) {
    const auto& limits = hardware.joints[j].limits;
    q[static_cast<Eigen::Index>(j)] = std::uniform_real_distribution<double>(
        limits.min_position_rad, limits.max_position_rad)(rng);
  }
  return q;
}

Eigen::Vector3d log_rotation(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd angle_axis(R);
  return angle_axis.angle() * angle_axis.axis();
}

enum class Expressed { kWorld, kFrame };

// Central differences of the frame's pose, one joint at a time. A single joint turns everything
// downstream about one fixed axis, so R(q + h) R(q - h)^T = exp(w_W 2h) exactly and
// R(q - h)^T R(q + h) = exp(w_F 2h): the rotation part is exact up to rounding, the
// translation part O(h^2).
Jacobian numeric_jacobian(Kinematics& kinematics, int frame, const Eigen::VectorXd& q,
                          Expressed expressed) {
  const double h = 1e-6;
  Jacobian J = kinematics.make_jacobian();
  EXPECT_EQ(kinematics.update(q), hal::Status::kOk);
  const Eigen::Matrix3d R_WF = kinematics.X_WF(frame).linear();
  for (Eigen::Index j = 0; j < q.size(); ++j) {
    Eigen::VectorXd q_plus = q, q_minus = q;
    q_plus[j] += h;
    q_minus[j] -= h;
    EXPECT_EQ(kinematics.update(q_plus), hal::Status::kOk);
    const Eigen::Isometry3d X_plus = kinematics.X_WF(frame);
    EXPECT_EQ(kinematics.update(q_minus), hal::Status::kOk);
    const Eigen::Isometry3d X_minus = kinematics.X_WF(frame);
    const Eigen::Vector3d v_W = (X_plus.translation() - X_minus.translation()) / (2 * h);
    if (expressed == Expressed::kWorld) {
      J.col(j) << v_W, log_rotation(X_plus.linear() * X_minus.linear().transpose()) / (2 * h);
    } else {
      J.col(j) << R_WF.transpose() * v_W,
          log_rotation(X_minus.linear().transpose() * X_plus.linear()) / (2 * h);
    }
  }
  EXPECT_EQ(kinematics.update(q), hal::Status::kOk);
  return J;
}

TEST(Kinematics, PlanarArmTipMatchesClosedForm) {
  Kinematics kinematics(planar_arm(), kPlanarTip);
  const int tip = kinematics.frame_index("tip");
  Jacobian J = kinematics.make_jacobian();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-pi, pi);
  for (int trial = 0; trial < 20; ++trial) {
    const double q1 = angle(rng), q2 = angle(rng);
    ASSERT_EQ(kinematics.update(Eigen::Vector2d(q1, q2)), hal::Status::kOk);
    const Eigen::Isometry3d& X_WT = kinematics.X_WF(tip);
    const double c1 = std::cos(q1), s1 = std::sin(q1);
    const double c12 = std::cos(q1 + q2), s12 = std::sin(q1 + q2);
    EXPECT_TRUE(X_WT.translation().isApprox(
        Eigen::Vector3d(kL1M * c1 + kL2M * c12, kL1M * s1 + kL2M * s12, 0.0), 1e-14))
        << X_WT.translation().transpose();
    EXPECT_TRUE(X_WT.linear().isApprox(
        Eigen::AngleAxisd(q1 + q2, Eigen::Vector3d::UnitZ()).toRotationMatrix(), 1e-14));

    ASSERT_EQ(kinematics.jacobian_W(tip, J), hal::Status::kOk);
    Jacobian expected(6, 2);
    expected << -kL1M * s1 - kL2M * s12, -kL2M * s12,  //
        kL1M * c1 + kL2M * c12, kL2M * c12,            //
        0, 0,                                          //
        0, 0,                                          //
        0, 0,                                          //
        1, 1;
    EXPECT_LT((J - expected).cwiseAbs().maxCoeff(), 1e-14) << J;
  }
}

TEST(Kinematics, CameraPoseIsParentPoseTimesMount) {
  const hal::HardwareInfo hardware = planar_arm();
  Kinematics kinematics(hardware, kPlanarTip);
  const int camera = kinematics.frame_index("hand_eye");
  const int elbow_link = kinematics.frame_index("elbow");
  EXPECT_EQ(elbow_link, Kinematics::link_frame(kinematics.joint_index("elbow")));
  ASSERT_EQ(kinematics.update(Eigen::Vector2d(0.4, -1.1)), hal::Status::kOk);
  const Eigen::Isometry3d& X_WC = kinematics.X_WF(camera);
  EXPECT_TRUE(X_WC.isApprox(kinematics.X_WF(elbow_link) * hardware.cameras[0].X_PC, 1e-15));
  // Looking along the forearm, image y down (= world -z, as the arm stays in the plane).
  const Eigen::Vector3d forward_W(std::cos(-0.7), std::sin(-0.7), 0.0);
  EXPECT_TRUE(X_WC.linear().col(2).isApprox(forward_W, 1e-14));
  EXPECT_TRUE(X_WC.linear().col(1).isApprox(-Eigen::Vector3d::UnitZ(), 1e-14));
  EXPECT_TRUE(X_WC.translation().isApprox(
      kinematics.X_WF(kinematics.frame_index("tip")).translation(), 1e-15));
}

TEST(Kinematics, CameraJacobianInTheCameraFrameMatchesClosedForm) {
  Kinematics kinematics(planar_arm(), kPlanarTip);
  const int camera = kinematics.frame_index("hand_eye");
  Jacobian J_C = kinematics.make_jacobian();
  const double q1 = 0.3, q2 = 0.9;
  ASSERT_EQ(kinematics.update(Eigen::Vector2d(q1, q2)), hal::Status::kOk);
  ASSERT_EQ(kinematics.jacobian_F(camera, J_C), hal::Status::kOk);
  // Both joints turn the camera about world z = the camera's -y. The elbow swings the camera
  // sideways at kL2M per rad, to the forearm's left = the camera's -x; the shoulder moves it
  // at its distance from the base, perpendicular to the line from the base: in the camera frame
  // (-(kL2M + kL1M cos q2), 0, kL1M sin q2): sideways from the elbow's swing plus the upper
  // arm's part, which is forward along the optical axis when the elbow is bent.
  Jacobian expected(6, 2);
  expected << -(kL2M + kL1M * std::cos(q2)), -kL2M,  //
      0, 0,                                          //
      kL1M * std::sin(q2), 0,                        //
      0, 0,                                          //
      -1, -1,                                        //
      0, 0;
  EXPECT_LT((J_C - expected).cwiseAbs().maxCoeff(), 1e-14) << J_C;
}

TEST(Kinematics, JacobiansMatchCentralDifferencesOnABranchingTree) {
  std::mt19937 rng(20240611);
  const hal::HardwareInfo hardware = random_tree(rng);
  Kinematics kinematics(hardware, random_tree_frames(rng));
  ASSERT_EQ(kinematics.frame_count(), 1 + 6 + 1 + 2);
  Jacobian J = kinematics.make_jacobian();
  double worst = 0.0;
  for (int trial = 0; trial < 25; ++trial) {
    const Eigen::VectorXd q = random_configuration(hardware, rng);
    for (int frame = 0; frame < kinematics.frame_count(); ++frame) {
      SCOPED_TRACE("frame " + kinematics.frame_name(frame) + ", trial " + std::to_string(trial));
      for (const Expressed expressed : {Expressed::kWorld, Expressed::kFrame}) {
        const Jacobian numeric = numeric_jacobian(kinematics, frame, q, expressed);
        const hal::Status status = expressed == Expressed::kWorld ? kinematics.jacobian_W(frame, J)
                                                                  : kinematics.jacobian_F(frame, J);
        ASSERT_EQ(status, hal::Status::kOk);
        const double error = (J - numeric).cwiseAbs().maxCoeff();
        worst = std::max(worst, error);
        EXPECT_LT(error, 1e-8) << "analytic\n" << J << "\nnumeric\n" << numeric;
      }
    }
  }
  RecordProperty("worst_jacobian_error", ::testing::PrintToString(worst));
}

TEST(Kinematics, OnlyAncestorJointsHaveColumns) {
  std::mt19937 rng(3);
  const hal::HardwareInfo hardware = random_tree(rng);
  Kinematics kinematics(hardware, random_tree_frames(rng));
  ASSERT_EQ(kinematics.update(random_configuration(hardware, rng)), hal::Status::kOk);
  Jacobian J = kinematics.make_jacobian();
  auto columns = [&](const std::string& frame) {
    J.setConstant(std::numeric_limits<double>::quiet_NaN());  // Every entry must be written.
    EXPECT_EQ(kinematics.jacobian_W(kinematics.frame_index(frame), J), hal::Status::kOk);
    std::string used;
    for (int j = 0; j < kinematics.joint_count(); ++j) {
      EXPECT_FALSE(J.col(j).hasNaN());
      if (!J.col(j).isZero(0.0)) used += kinematics.joint_name(j);
    }
    return used;
  };
  EXPECT_EQ(columns("base"), "");
  EXPECT_EQ(columns("a"), "a");  // On its joint's axis: no linear part, but it turns.
  EXPECT_EQ(columns("tcp"), "abc");
  EXPECT_EQ(columns("cam"), "abc");
  EXPECT_EQ(columns("e"), "ade");
  EXPECT_EQ(columns("f"), "f");
}

TEST(Kinematics, RigOrderFollowsTheGroups) {
  std::mt19937 rng(5);
  const hal::HardwareInfo hardware = random_tree(rng);
  Kinematics by_tree(hardware), by_rig(hardware);
  // Groups: {e, d, f}, {c, a, b}; the tree's order is a, f, b, d, c, e.
  ASSERT_EQ(by_rig.rig_joint_count(), 6);
  const std::vector<int> expected{5, 3, 1, 4, 0, 2};
  EXPECT_EQ(std::vector<int>(by_rig.rig_to_tree().begin(), by_rig.rig_to_tree().end()), expected);
  const Eigen::VectorXd q = random_configuration(hardware, rng);
  std::vector<double> q_rig(6);
  for (std::size_t i = 0; i < q_rig.size(); ++i) q_rig[i] = q[expected[i]];
  ASSERT_EQ(by_tree.update(q), hal::Status::kOk);
  ASSERT_EQ(by_rig.update_rig_order(q_rig), hal::Status::kOk);
  for (int frame = 0; frame < by_tree.frame_count(); ++frame) {
    EXPECT_TRUE(by_tree.X_WF(frame).isApprox(by_rig.X_WF(frame), 0.0));
  }
  EXPECT_EQ(by_rig.update_rig_order(std::vector<double>(5, 0.0)), hal::Status::kRejected);
}

TEST(Kinematics, UngroupedJointsAreAtZeroInRigOrder) {
  hal::HardwareInfo hardware = planar_arm();
  hardware.groups = {sim_group("arm", {"elbow"})};
  Kinematics kinematics(hardware);
  ASSERT_EQ(kinematics.update_rig_order(std::vector<double>{0.5}), hal::Status::kOk);
  EXPECT_EQ(kinematics.q_rad()[0], 0.0);
  EXPECT_EQ(kinematics.q_rad()[1], 0.5);
}

TEST(Kinematics, BaseIsTheWorldAndZeroIsTheRestPose) {
  const hal::HardwareInfo hardware = planar_arm();
  Kinematics kinematics(hardware, kPlanarTip);
  EXPECT_EQ(kinematics.frame_index("base"), 0);
  EXPECT_TRUE(kinematics.X_WF(0).isApprox(Eigen::Isometry3d::Identity(), 0.0));
  EXPECT_TRUE(kinematics.X_WF(kinematics.frame_index("tip"))
                  .translation()
                  .isApprox(Eigen::Vector3d(kL1M + kL2M, 0, 0), 1e-15));
}

TEST(Kinematics, RejectsBadInputsWithoutTouchingThePoses) {
  Kinematics kinematics(planar_arm(), kPlanarTip);
  const int tip = kinematics.frame_index("tip");
  ASSERT_EQ(kinematics.update(Eigen::Vector2d(0.2, 0.3)), hal::Status::kOk);
  const Eigen::Isometry3d before = kinematics.X_WF(tip);
  EXPECT_EQ(kinematics.update(std::vector<double>{0.1}), hal::Status::kRejected);
  EXPECT_EQ(kinematics.update(std::vector<double>{0.1, std::nan("")}), hal::Status::kRejected);
  EXPECT_EQ(kinematics.update(Eigen::Vector2d(std::numeric_limits<double>::infinity(), 0.0)),
            hal::Status::kRejected);
  EXPECT_TRUE(kinematics.X_WF(tip).isApprox(before, 0.0));
  EXPECT_EQ(kinematics.q_rad()[1], 0.3);

  Jacobian wrong(6, 3);
  EXPECT_EQ(kinematics.jacobian_W(tip, wrong), hal::Status::kRejected);
  Jacobian J = kinematics.make_jacobian();
  EXPECT_EQ(kinematics.jacobian_W(-1, J), hal::Status::kRejected);
  EXPECT_EQ(kinematics.jacobian_F(kinematics.frame_count(), J), hal::Status::kRejected);
  EXPECT_EQ(kinematics.find_frame("nowhere"), -1);
  EXPECT_EQ(kinematics.find_joint("tip"), -1);
  EXPECT_THROW(kinematics.frame_index("nowhere"), std::out_of_range);
  EXPECT_THROW(kinematics.joint_index("tip"), std::out_of_range);
}

// The message of the std::invalid_argument the constructor throws, or "" if it does not.
std::string construction_error(const hal::HardwareInfo& hardware,
                               const std::vector<FixedFrameInfo>& frames = {}) {
  try {
    Kinematics kinematics(hardware, frames);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

void expect_refused(const std::string& error, const std::string& expected) {
  EXPECT_NE(error.find(expected), std::string::npos)
      << "expected '" << expected << "' in '" << error << "'";
}

TEST(Kinematics, RefusesBrokenTreesNamingTheOffender) {
  hal::HardwareInfo unknown_parent = planar_arm();
  unknown_parent.joints[1].parent = "shouldr";
  expect_refused(construction_error(unknown_parent),
                 "joint 'elbow' hangs from 'shouldr', which is neither 'base' nor a joint");

  hal::HardwareInfo cycle = planar_arm();
  cycle.joints[0].parent = "elbow";
  expect_refused(construction_error(cycle), "cycle: 'shoulder' -> 'elbow' -> 'shoulder'");

  hal::HardwareInfo self_parent = planar_arm();
  self_parent.joints[1].parent = "elbow";
  expect_refused(construction_error(self_parent), "cycle: 'elbow' -> 'elbow'");

  hal::HardwareInfo child_first = planar_arm();
  std::swap(child_first.joints[0], child_first.joints[1]);
  expect_refused(construction_error(child_first),
                 "joint 'elbow' comes before its parent 'shoulder'");

  hal::HardwareInfo duplicate = planar_arm();
  duplicate.joints[1].name = "shoulder";
  duplicate.joints[1].parent = "base";
  expect_refused(construction_error(duplicate), "two frames are named 'shoulder'");

  hal::HardwareInfo camera_clash = planar_arm();
  camera_clash.cameras[0].name = "elbow";
  expect_refused(construction_error(camera_clash), "two frames are named 'elbow'");

  hal::HardwareInfo lost_camera = planar_arm();
  lost_camera.cameras[0].parent_frame = "wrist";
  expect_refused(construction_error(lost_camera), "camera 'hand_eye' is mounted on 'wrist'");

  expect_refused(construction_error(planar_arm(), {{"tip", "hand", translation(0, 0, 0)}}),
                 "frame 'tip' hangs from 'hand'");

  hal::HardwareInfo long_axis = planar_arm();
  long_axis.joints[0].axis_J = Eigen::Vector3d(0, 0, 2);
  expect_refused(construction_error(long_axis), "joint 'shoulder' has a non-unit axis");

  hal::HardwareInfo sheared = planar_arm();
  sheared.cameras[0].X_PC.linear()(0, 1) = 0.1;
  expect_refused(construction_error(sheared), "X_PC is not a rotation");

  hal::HardwareInfo bad_group = planar_arm();
  bad_group.groups[0].joints.push_back("wrist");
  expect_refused(construction_error(bad_group), "group 'arm' names unknown joint 'wrist'");

  hal::HardwareInfo twice = planar_arm();
  twice.groups.push_back(sim_group("again", {"elbow"}));
  expect_refused(construction_error(twice), "joint 'elbow' is listed twice");

  EXPECT_EQ(construction_error(planar_arm(), kPlanarTip), "");
}

TEST(Kinematics, UpdateAndJacobiansDoNotAllocate) {
  std::mt19937 rng(11);
  const hal::HardwareInfo hardware = random_tree(rng);
  Kinematics kinematics(hardware, random_tree_frames(rng));
  const int tcp = kinematics.frame_index("tcp");
  const int camera = kinematics.frame_index("cam");
  Jacobian J_W = kinematics.make_jacobian();
  Jacobian J_C = kinematics.make_jacobian();
  std::vector<Eigen::VectorXd> configurations;
  for (int i = 0; i < 10; ++i) configurations.push_back(random_configuration(hardware, rng));
  std::vector<double> q_rig(static_cast<std::size_t>(kinematics.rig_joint_count()), 0.1);
  Eigen::Vector3d sink = Eigen::Vector3d::Zero();

  const auto before = runtime::thread_allocation_count();
  for (const Eigen::VectorXd& q : configurations) {
    bool ok = kinematics.update(q) == hal::Status::kOk;
    ok = ok && kinematics.jacobian_W(tcp, J_W) == hal::Status::kOk;
    ok = ok && kinematics.jacobian_F(camera, J_C) == hal::Status::kOk;
    ok = ok && kinematics.update_rig_order(q_rig) == hal::Status::kOk;
    sink += kinematics.X_WF(camera).translation() + J_W.col(0).head<3>() + J_C.col(0).tail<3>();
    EXPECT_TRUE(ok);
  }
  EXPECT_EQ(runtime::thread_allocation_count() - before, 0u);
  EXPECT_TRUE(sink.allFinite());
}

}  // namespace
}  // namespace cambio::control
