#include "stereo_calibration_run.hpp"

#include <cmath>
#include <iomanip>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "right_camera_mount.hpp"
#include "stereo_calibration.hpp"
#include "stereo_image_pairs.hpp"

namespace cambio::app {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

struct RefusedView {
  std::string view_id;
  std::string reason;
};

struct FoundViews {
  std::vector<StereoView> views;
  std::vector<RefusedView> refused;
};

FoundViews find_boards(const std::vector<StereoImagePair>& pairs, const ChessboardSpec& board,
                       const config::CameraConfig& left, const config::CameraConfig& right) {
  FoundViews found;
  const std::string pattern =
      std::to_string(board.inner_columns) + "x" + std::to_string(board.inner_rows);
  for (const auto& pair : pairs) {
    const auto left_px =
        find_board_corners_px(read_calibration_image(pair.left, left, "--images"), board);
    const auto right_px =
        find_board_corners_px(read_calibration_image(pair.right, right, "--images"), board);
    std::string missing;
    if (!left_px) missing = pair.left.filename().string();
    if (!right_px) missing += (missing.empty() ? "" : " and ") + pair.right.filename().string();
    if (missing.empty()) {
      found.views.push_back({pair.view_id, *left_px, *right_px});
    } else {
      found.refused.push_back({pair.view_id, "no " + pattern + " board found in " + missing});
    }
  }
  return found;
}

void print_camera(std::ostream& report, const std::string& name, const CameraCalibration& c) {
  const hal::PlumbBobDistortion& d = c.distortion;
  report << "  " << name << ": focal " << c.focal_x_px << ", " << c.focal_y_px
         << " px, principal point " << c.principal_x_px << ", " << c.principal_y_px
         << " px; k1 k2 p1 p2 k3 " << d.k1 << " " << d.k2 << " " << d.p1 << " " << d.p2 << " "
         << d.k3 << "\n";
}

void print_results(std::ostream& report, const config::RigConfig& rig,
                   const StereoCalibration& calibration, const FoundViews& found) {
  report << std::fixed << std::setprecision(3);
  for (const auto& view : calibration.views) {
    report << "view " << view.view_id << ": RMS " << view.rms_px << " px (left " << view.left_rms_px
           << ", right " << view.right_rms_px << ")\n";
  }
  report << "overall: RMS " << calibration.rms_px << " px over " << calibration.views.size()
         << " views (each camera alone: left " << calibration.left.mono_rms_px << ", right "
         << calibration.right.mono_rms_px << " px)";
  if (!found.refused.empty()) report << "; " << found.refused.size() << " refused";
  report << "\n";
  report << std::setprecision(4);
  print_camera(report, rig.stereo->left_camera, calibration.left);
  print_camera(report, rig.stereo->right_camera, calibration.right);
  const Eigen::Vector3d t_m = calibration.X_LR.translation();
  report << std::setprecision(5) << "  X_LR: t = [" << t_m.x() << ", " << t_m.y() << ", " << t_m.z()
         << "] m, baseline " << t_m.norm() << " m, rotated "
         << Eigen::AngleAxisd(calibration.X_LR.rotation()).angle() * kDegPerRad << " deg\n";
}

}  // namespace

StereoCalibrationOutcome run_stereo_calibration(const StereoCalibrationInputs& inputs,
                                                OutputDirectory& out, std::ostream& report) {
  const config::RigConfig& rig = inputs.rig;
  if (!rig.stereo) {
    throw CalibrationInputError("--rig: rig '" + rig.name + "' (" + rig.source_file +
                                ") has no stereo section naming its left and right cameras");
  }
  const config::CameraConfig& left = *rig.find_camera(rig.stereo->left_camera);
  const config::CameraConfig& right = *rig.find_camera(rig.stereo->right_camera);
  if (left.width_px != right.width_px || left.height_px != right.height_px) {
    throw CalibrationInputError("--rig: the stereo cameras of rig '" + rig.name +
                                "' differ in size; calibrate stereo needs one size for both");
  }

  const std::vector<StereoImagePair> pairs = find_stereo_image_pairs(inputs.images_dir);
  const FoundViews found = find_boards(pairs, inputs.board, left, right);
  report << "calibrate stereo: " << pairs.size() << " views in " << inputs.images_dir.string()
         << ", " << inputs.provenance.board << "\n";
  for (const auto& refused : found.refused) {
    report << "refused view " << refused.view_id << ": " << refused.reason << "\n";
  }
  if (found.views.size() < kMinStereoViews) {
    report << "calibrate stereo: " << found.views.size()
           << " views have the board in both images; at least " << kMinStereoViews
           << " are needed (a fit from fewer trades distortion for pose)\n";
    return StereoCalibrationOutcome::kTooFewViews;
  }

  const StereoCalibration calibration =
      calibrate_stereo(found.views, inputs.board, left.width_px, left.height_px);
  print_results(report, rig, calibration, found);

  const config::Pose right_mount = right_camera_mount(rig, calibration.X_LR);
  out.stage(kRigCalibrationFileName,
            rig_camera_calibration_yaml(rig, calibration, right_mount, inputs.provenance));
  const StereoRectification& rectified = calibration.rectification;
  out.stage(left.name + ".yaml",
            ros_camera_info_yaml(left.name, calibration.left, rectified.R_left, rectified.P_left));
  out.stage(right.name + ".yaml", ros_camera_info_yaml(right.name, calibration.right,
                                                       rectified.R_right, rectified.P_right));
  out.commit();
  report << "wrote " << (out.path() / kRigCalibrationFileName).string() << " (the rig's "
         << "camera_calibration), " << (out.path() / (left.name + ".yaml")).string() << " and "
         << (out.path() / (right.name + ".yaml")).string() << " (ROS camera_info)\n";
  return StereoCalibrationOutcome::kCalibrated;
}

}  // namespace cambio::app
