// The kinematics against the simulator's ground truth: the shipped rig, described once in YAML,
// becomes both the HAL's HardwareInfo (what control/ sees) and the MuJoCo model (the sim's MJCF
// generator). At random joint positions within the limits, every link, both eye cameras and a
// point on each gripper must sit where MuJoCo puts them, and the Jacobians must be MuJoCo's
// (mj_jac). Nothing renders: the joints are written into qpos and MuJoCo's kinematics run.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "../sim/sim_test_support.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/control/kinematics.hpp"
#include "cambio/hal/triple_buffer.hpp"
#include "cambio/sim/ground_truth.hpp"
#include "cambio/sim/mjcf_builder.hpp"
#include "cambio/sim/world.hpp"

namespace cambio::control {
namespace {

constexpr int kConfigurations = 25;
constexpr double kPositionToleranceM = 1e-9;
constexpr double kRotationToleranceRad = 1e-9;
// Jacobian entries are m/rad (linear) and rad/rad (angular): the same bound.
constexpr double kJacobianTolerance = 1e-9;
// The end of the sim's finger boxes on a gripper link (sim/src/mjcf_builder.cpp write_finger:
// a box at x = 0.078 m with half-size 0.004 m): a point to reach with, off the joint axis.
constexpr double kFingerTipXM = 0.082;

struct WorstError {
  double position_m = 0.0;
  double rotation_rad = 0.0;
  std::string position_frame;
  std::string rotation_frame;

  void add(const std::string& frame, const Eigen::Isometry3d& X_expected,
           const Eigen::Isometry3d& X_actual) {
    const double position = (X_expected.translation() - X_actual.translation()).norm();
    // The angle of R_e^T R_a; AngleAxis goes through a quaternion and atan2, accurate near 0.
    const double rotation =
        Eigen::AngleAxisd(X_expected.linear().transpose() * X_actual.linear()).angle();
    EXPECT_LE(position, kPositionToleranceM) << frame;
    EXPECT_LE(rotation, kRotationToleranceRad) << frame;
    if (position > position_m) {
      position_m = position;
      position_frame = frame;
    }
    if (rotation > rotation_rad) {
      rotation_rad = rotation;
      rotation_frame = frame;
    }
  }
};

Eigen::Isometry3d pose_of_body(const mjData* data, int body) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Map<const Eigen::Vector3d>(data->xpos + 3 * body);
  X.linear() =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(data->xmat + 9 * body);
  return X;
}

class KinematicsSimTruth : public ::testing::Test {
 protected:
  KinematicsSimTruth()
      : rig_(sim::testing::load_shipped_rig()),
        hardware_(config::hardware_description(rig_)),
        world_(rig_, sim::testing::load_shipped_scene("table")),
        kinematics_(hardware_, gripper_tips()) {}

  static std::vector<std::string> grippers() { return {"left_gripper", "right_gripper"}; }

  static std::vector<FixedFrameInfo> gripper_tips() {
    std::vector<FixedFrameInfo> tips;
    for (const auto& gripper : grippers()) {
      Eigen::Isometry3d X_LT = Eigen::Isometry3d::Identity();
      X_LT.translation() = Eigen::Vector3d(kFingerTipXM, 0.0, 0.0);
      tips.push_back({gripper + "_tip", gripper, X_LT});
    }
    return tips;
  }

  /// Random positions within every joint's limits (HardwareInfo order), written into the sim's
  /// qpos too (the mirrored finger at minus its gripper, as the sim's equality constraint holds
  /// it), then MuJoCo's forward kinematics.
  Eigen::VectorXd place_random(std::mt19937& rng) {
    mjModel* model = world_.model();
    mjData* data = world_.data();
    Eigen::VectorXd q(kinematics_.joint_count());
    for (int j = 0; j < kinematics_.joint_count(); ++j) {
      const hal::JointInfo& joint = hardware_.joints[static_cast<std::size_t>(j)];
      q[j] = std::uniform_real_distribution<double>(joint.limits.min_position_rad,
                                                    joint.limits.max_position_rad)(rng);
      data->qpos[sim_joint(joint.name).qpos_address] = q[j];
      const int mimic = mj_name2id(model, mjOBJ_JOINT, (joint.name + sim::kMimicSuffix).c_str());
      if (mimic >= 0) data->qpos[model->jnt_qposadr[mimic]] = -q[j];
    }
    mj_kinematics(model, data);
    mj_comPos(model, data);  // mj_jac needs the com-based quantities.
    return q;
  }

  const sim::JointIndex& sim_joint(const std::string& name) const {
    const int index = world_.find_joint(name);
    EXPECT_GE(index, 0) << name;
    return world_.joints().at(static_cast<std::size_t>(index));
  }

  /// The MuJoCo body a frame of the kinematics moves with, and the frame's origin in the world
  /// according to MuJoCo.
  int body_of(int frame) const {
    const std::string& name = kinematics_.frame_name(frame);
    const mjModel* model = world_.model();
    if (name == Kinematics::kBase) return 0;
    if (const int camera = mj_name2id(model, mjOBJ_CAMERA, name.c_str()); camera >= 0) {
      return model->cam_bodyid[camera];
    }
    const std::string link = name.ends_with("_tip") ? name.substr(0, name.size() - 4) : name;
    return mj_name2id(model, mjOBJ_BODY, link.c_str());
  }

  config::RigConfig rig_;
  hal::HardwareInfo hardware_;
  sim::World world_;
  Kinematics kinematics_;
};

TEST_F(KinematicsSimTruth, PosesMatchTheSimulatorAtRandomConfigurations) {
  ASSERT_EQ(hardware_.cameras.size(), 2u);  // Both eyes.
  std::mt19937 rng(20240611);
  hal::TripleBuffer<sim::WorldSnapshot> no_snapshots;
  WorstError worst;
  for (int trial = 0; trial < kConfigurations; ++trial) {
    SCOPED_TRACE("configuration " + std::to_string(trial));
    const Eigen::VectorXd q = place_random(rng);
    ASSERT_EQ(kinematics_.update(q), hal::Status::kOk);
    // The ground truth copies the world's state and runs MuJoCo's kinematics on its copy; with
    // nothing published it keeps that state, so its X_WC (MuJoCo's camera frame turned into the
    // optical frame) and X_WL read the configuration just written.
    sim::GroundTruth truth(world_, no_snapshots);

    worst.add("base", truth.X_WL("base"), kinematics_.X_WF(0));
    for (const hal::JointInfo& joint : hardware_.joints) {
      worst.add(joint.name, truth.X_WL(joint.name),
                kinematics_.X_WF(kinematics_.frame_index(joint.name)));
    }
    for (const hal::CameraInfo& camera : hardware_.cameras) {
      worst.add(camera.name, truth.X_WC(camera.name),
                kinematics_.X_WF(kinematics_.frame_index(camera.name)));
    }
    for (const std::string& gripper : grippers()) {
      // The tip: a point fixed on the gripper link.
      const std::string tip = gripper + "_tip";
      Eigen::Isometry3d X_WT = truth.X_WL(gripper);
      X_WT.translation() += X_WT.linear() * Eigen::Vector3d(kFingerTipXM, 0.0, 0.0);
      worst.add(tip, X_WT, kinematics_.X_WF(kinematics_.frame_index(tip)));
      // The sim's mirrored finger turns about the gripper's axis by minus its angle: the
      // gripper joint's frame turned the other way.
      const hal::JointInfo& joint = *hardware_.find_joint(gripper);
      const Eigen::Isometry3d X_WM =
          kinematics_.X_WF(kinematics_.frame_index(joint.parent)) * joint.X_PJ *
          Eigen::AngleAxisd(-q[kinematics_.joint_index(gripper)], joint.axis_J);
      const int mimic_body =
          mj_name2id(world_.model(), mjOBJ_BODY, (gripper + sim::kMimicSuffix).c_str());
      ASSERT_GE(mimic_body, 0);
      worst.add(gripper + sim::kMimicSuffix, pose_of_body(world_.data(), mimic_body), X_WM);
    }
  }
  RecordProperty("worst_position_m", ::testing::PrintToString(worst.position_m));
  RecordProperty("worst_position_frame", worst.position_frame);
  RecordProperty("worst_rotation_rad", ::testing::PrintToString(worst.rotation_rad));
  RecordProperty("worst_rotation_frame", worst.rotation_frame);
}

TEST_F(KinematicsSimTruth, JacobiansMatchMujocoAtRandomConfigurations) {
  std::mt19937 rng(17);
  const mjModel* model = world_.model();
  const int nv = model->nv;
  // MuJoCo's Jacobians are 3 x nv, row-major, one column per degree of freedom.
  Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor> jacp(3, nv), jacr(3, nv);
  Jacobian J_W = kinematics_.make_jacobian();
  Jacobian J_F = kinematics_.make_jacobian();
  std::vector<int> dof_of_joint;
  for (int j = 0; j < kinematics_.joint_count(); ++j) {
    dof_of_joint.push_back(sim_joint(kinematics_.joint_name(j)).dof_address);
  }
  double worst = 0.0;
  for (int trial = 0; trial < kConfigurations; ++trial) {
    SCOPED_TRACE("configuration " + std::to_string(trial));
    ASSERT_EQ(kinematics_.update(place_random(rng)), hal::Status::kOk);
    for (int frame = 1; frame < kinematics_.frame_count(); ++frame) {
      const std::string& name = kinematics_.frame_name(frame);
      const int body = body_of(frame);
      ASSERT_GT(body, 0) << name;
      const Eigen::Vector3d p_WF = kinematics_.X_WF(frame).translation();
      mj_jac(model, world_.data(), jacp.data(), jacr.data(), p_WF.data(), body);
      ASSERT_EQ(kinematics_.jacobian_W(frame, J_W), hal::Status::kOk);
      Eigen::Matrix<double, 6, Eigen::Dynamic> mujoco = Eigen::MatrixXd::Zero(6, nv);
      mujoco << jacp, jacr;
      for (int j = 0; j < kinematics_.joint_count(); ++j) {
        const double error = (J_W.col(j) - mujoco.col(dof_of_joint[static_cast<std::size_t>(j)]))
                                 .cwiseAbs()
                                 .maxCoeff();
        worst = std::max(worst, error);
        EXPECT_LE(error, kJacobianTolerance) << name << ", joint " << kinematics_.joint_name(j);
        mujoco.col(dof_of_joint[static_cast<std::size_t>(j)]).setZero();
      }
      // No other degree of freedom (mirrored fingers, free objects) moves a frame of the rig.
      EXPECT_TRUE(mujoco.isZero(0.0)) << name;

      // In the frame itself: the world Jacobian's halves turned by R_FW.
      ASSERT_EQ(kinematics_.jacobian_F(frame, J_F), hal::Status::kOk);
      const Eigen::Matrix3d R_FW = kinematics_.X_WF(frame).linear().transpose();
      Jacobian expected(6, J_W.cols());
      expected << R_FW * J_W.topRows<3>(), R_FW * J_W.bottomRows<3>();
      EXPECT_LE((J_F - expected).cwiseAbs().maxCoeff(), 1e-15) << name;
    }
  }
  RecordProperty("worst_jacobian_error", ::testing::PrintToString(worst));
}

}  // namespace
}  // namespace cambio::control
