#include "hand_eye_calibration_run.hpp"

#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "cambio/config/hardware_description.hpp"
#include "cambio/control/kinematics.hpp"
#include "hand_eye_calibration.hpp"
#include "hand_eye_views.hpp"
#include "right_camera_mount.hpp"
#include "stereo_image_pairs.hpp"

namespace cambio::app {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
/// Below this the motions' axes are one axis for the mount's rotation about it.
constexpr double kMinMotionAxisAngle_rad = 5.0 / kDegPerRad;

const config::CameraConfig& moving_camera(const config::RigConfig& rig, const std::string& name) {
  const config::CameraConfig* camera = rig.find_camera(name);
  if (camera == nullptr) {
    std::string known;
    for (const auto& c : rig.cameras) known += (known.empty() ? "" : ", ") + c.name;
    throw CalibrationInputError("--camera: rig '" + rig.name + "' has no camera '" + name +
                                "' (its cameras: " + known + ")");
  }
  if (camera->parent == "base") {
    throw CalibrationInputError("--camera: camera '" + name +
                                "' is fixed to the base: no joint moves it, so hand-eye "
                                "calibration cannot see its mount");
  }
  return *camera;
}

/// The joints from the camera's link down to the base: each view must read them all.
std::vector<std::string> chain_joints(const config::RigConfig& rig, std::string link) {
  std::vector<std::string> chain;
  while (link != "base" && chain.size() <= rig.joints.size()) {
    const config::JointConfig* joint = rig.find_joint(link);
    if (joint == nullptr) break;
    chain.push_back(joint->name);
    link = joint->parent;
  }
  return chain;
}

/// The board's pose in the camera from its corners, and the reprojection RMS.
Eigen::Isometry3d board_in_camera(const std::vector<cv::Point2f>& corners_px,
                                  const ChessboardSpec& board, const config::CameraConfig& camera,
                                  double& rms_px) {
  const cv::Matx33d K(camera.focal_x_px, 0.0, camera.principal_x_px, 0.0, camera.focal_y_px,
                      camera.principal_y_px, 0.0, 0.0, 1.0);
  const std::array<double, 5> d = camera.distortion.opencv_order();
  const cv::Mat distortion(1, 5, CV_64F, const_cast<double*>(d.data()));
  const std::vector<cv::Point3f> object_m = board_corners_m(board);
  cv::Mat rvec, tvec;
  cv::solvePnP(object_m, corners_px, K, distortion, rvec, tvec, false, cv::SOLVEPNP_IPPE);
  cv::solvePnPRefineLM(object_m, corners_px, K, distortion, rvec, tvec);
  std::vector<cv::Point2f> reprojected;
  cv::projectPoints(object_m, rvec, tvec, K, distortion, reprojected);
  double sum = 0.0;
  for (std::size_t i = 0; i < reprojected.size(); ++i) {
    const cv::Point2f e = reprojected[i] - corners_px[i];
    sum += e.dot(e);
  }
  rms_px = std::sqrt(sum / static_cast<double>(reprojected.size()));
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d R_CT;
  Eigen::Vector3d t_CT;
  cv::cv2eigen(R, R_CT);
  cv::cv2eigen(tvec, t_CT);
  Eigen::Isometry3d X_CT = Eigen::Isometry3d::Identity();
  X_CT.linear() = R_CT;
  X_CT.translation() = t_CT;
  return X_CT;
}

}  // namespace

HandEyeCalibrationOutcome run_hand_eye_calibration(const HandEyeCalibrationInputs& inputs,
                                                   OutputDirectory& out, std::ostream& report) {
  const config::RigConfig& rig = inputs.rig;
  const config::CameraConfig& camera = moving_camera(rig, inputs.camera);
  const std::vector<std::string> chain = chain_joints(rig, camera.parent);
  control::Kinematics kinematics(config::hardware_description(rig));
  const int link_frame = kinematics.frame_index(camera.parent);

  const std::vector<HandEyeViewFiles> files = find_hand_eye_views(inputs.views_dir);
  report << "calibrate hand-eye: " << files.size() << " views of camera " << camera.name << " in "
         << inputs.views_dir.string() << ", " << inputs.provenance.board << "\n";
  std::vector<HandEyeView> views;
  std::vector<double> q(static_cast<std::size_t>(kinematics.joint_count()), 0.0);
  const std::string pattern =
      std::to_string(inputs.board.inner_columns) + "x" + std::to_string(inputs.board.inner_rows);
  for (const HandEyeViewFiles& view : files) {
    const std::map<std::string, double> readings = read_joint_readings(view.joints);
    std::fill(q.begin(), q.end(), 0.0);
    for (const auto& [name, value] : readings) {
      const int joint = kinematics.find_joint(name);
      if (joint < 0) {
        throw CalibrationInputError("--views: " + view.joints.string() + ": rig '" + rig.name +
                                    "' has no joint '" + name + "'");
      }
      q[static_cast<std::size_t>(joint)] = value;
    }
    for (const std::string& joint : chain) {
      if (readings.count(joint) == 0) {
        throw CalibrationInputError("--views: " + view.joints.string() + ": no reading of joint '" +
                                    joint + "', which moves camera " + camera.name);
      }
    }
    const auto corners =
        find_board_corners_px(read_calibration_image(view.image, camera, "--views"), inputs.board);
    if (!corners) {
      report << "refused view " << view.view_id << ": no " << pattern << " board found in "
             << view.image.filename().string() << "\n";
      continue;
    }
    (void)kinematics.update(q);
    HandEyeView found;
    found.view_id = view.view_id;
    found.X_BP = kinematics.X_WF(link_frame);
    found.X_CT = board_in_camera(*corners, inputs.board, camera, found.pnp_rms_px);
    for (const cv::Point2f& corner : *corners) found.corners_px.emplace_back(corner.x, corner.y);
    views.push_back(found);
  }
  if (views.size() < kMinHandEyeViews) {
    report << "calibrate hand-eye: " << views.size() << " views have the whole board; at least "
           << kMinHandEyeViews << " are needed\n";
    return HandEyeCalibrationOutcome::kTooFewViews;
  }
  const double axis_spread_rad = largest_motion_axis_angle_rad(views);
  if (axis_spread_rad < kMinMotionAxisAngle_rad) {
    report << "calibrate hand-eye: the views turn the camera about one axis only (the motions' "
              "axes are within "
           << axis_spread_rad * kDegPerRad
           << " deg of each other); move at least two different joints between views\n";
    return HandEyeCalibrationOutcome::kDegenerateMotion;
  }

  HandEyeTarget target;
  for (const cv::Point3f& corner : board_corners_m(inputs.board)) {
    target.corners_T_m.emplace_back(corner.x, corner.y, corner.z);
  }
  target.focal_x_px = camera.focal_x_px;
  target.focal_y_px = camera.focal_y_px;
  target.principal_x_px = camera.principal_x_px;
  target.principal_y_px = camera.principal_y_px;
  target.distortion = camera.distortion;
  const HandEyeCalibration calibration = calibrate_hand_eye(views, target);
  report << std::fixed << std::setprecision(3);
  for (const HandEyeView& view : views) {
    report << "view " << view.view_id << ": board pose RMS " << view.pnp_rms_px << " px\n";
  }
  const config::Pose mount = pose_of(calibration.X_PC);
  std::ostringstream summary;
  summary << std::fixed << std::setprecision(2) << views.size() << " views; reprojection RMS "
          << calibration.reprojection_rms_px
          << " px through the mount and one board pose; each view's board in base agrees to "
          << calibration.board_spread_m * 1000.0 << " mm and "
          << calibration.board_spread_rad * kDegPerRad << " deg RMS.";
  report << std::setprecision(5) << "  " << camera.name << " on " << camera.parent
         << ": origin_xyz_m [" << mount.xyz_m[0] << ", " << mount.xyz_m[1] << ", " << mount.xyz_m[2]
         << "], origin_rpy_deg [" << mount.rpy_rad[0] * kDegPerRad << ", "
         << mount.rpy_rad[1] * kDegPerRad << ", " << mount.rpy_rad[2] * kDegPerRad << "]\n  "
         << summary.str() << "\n";
  out.stage(kRigCalibrationFileName,
            rig_camera_mount_yaml(rig, camera.name, mount, summary.str(), inputs.provenance));
  out.commit();
  report << "wrote " << (out.path() / kRigCalibrationFileName).string()
         << " (the rig's camera_calibration)\n";
  return HandEyeCalibrationOutcome::kCalibrated;
}

}  // namespace cambio::app
