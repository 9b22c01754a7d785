#include "calibration_files.hpp"

#include <cmath>
#include <numbers>
#include <span>
#include <sstream>

#include <yaml-cpp/yaml.h>

namespace cambio::app {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// Enough digits that a value read back is the value fitted to far below its uncertainty.
constexpr int kSignificantDigits = 12;

void emit_list(YAML::Emitter& out, std::span<const double> values) {
  out << YAML::Flow << YAML::BeginSeq;
  for (const double value : values) out << value;
  out << YAML::EndSeq;
}

void emit_intrinsics(YAML::Emitter& out, const CameraCalibration& camera) {
  out << YAML::Key << "width_px" << YAML::Value << camera.width_px;
  out << YAML::Key << "height_px" << YAML::Value << camera.height_px;
  out << YAML::Key << "focal_x_px" << YAML::Value << camera.focal_x_px;
  out << YAML::Key << "focal_y_px" << YAML::Value << camera.focal_y_px;
  out << YAML::Key << "principal_point_px" << YAML::Value;
  emit_list(out, std::array{camera.principal_x_px, camera.principal_y_px});
  const hal::PlumbBobDistortion& d = camera.distortion;
  out << YAML::Key << "distortion" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "k1" << YAML::Value << d.k1 << YAML::Key << "k2" << YAML::Value << d.k2;
  out << YAML::Key << "p1" << YAML::Value << d.p1 << YAML::Key << "p2" << YAML::Value << d.p2;
  out << YAML::Key << "k3" << YAML::Value << d.k3 << YAML::EndMap;
}

void emit_matrix(YAML::Emitter& out, const char* key, int rows, int cols,
                 std::span<const double> data) {
  out << YAML::Key << key << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "rows" << YAML::Value << rows;
  out << YAML::Key << "cols" << YAML::Value << cols;
  out << YAML::Key << "data" << YAML::Value;
  emit_list(out, data);
  out << YAML::EndMap;
}

void emit_mount(YAML::Emitter& out, const config::Pose& mount) {
  out << YAML::Key << "origin_xyz_m" << YAML::Value;
  emit_list(out, mount.xyz_m);
  const std::array<double, 3> rpy_deg = {
      mount.rpy_rad[0] * kDegPerRad, mount.rpy_rad[1] * kDegPerRad, mount.rpy_rad[2] * kDegPerRad};
  out << YAML::Key << "origin_rpy_deg" << YAML::Value;
  emit_list(out, rpy_deg);
}

std::string fixed(double value, int decimals) {
  std::ostringstream text;
  text.setf(std::ios::fixed);
  text.precision(decimals);
  text << value;
  return text.str();
}

}  // namespace

std::string rig_camera_calibration_yaml(const config::RigConfig& rig,
                                        const StereoCalibration& calibration,
                                        const config::Pose& right_mount,
                                        const CalibrationProvenance& provenance) {
  const Eigen::Vector3d t_m = calibration.X_LR.translation();
  const Eigen::AngleAxisd rotation(calibration.X_LR.rotation());
  std::ostringstream header;
  header << "# Camera calibration of rig " << rig.name << ", written by\n#   "
         << provenance.command_line << "\n# from " << calibration.views.size()
         << " stereo views of a chessboard (" << provenance.board << "); reprojection RMS "
         << fixed(calibration.rms_px, 3) << " px.\n"
         << "# The right camera in the left's optical frame (X_LR, x right, y down, z forward): "
         << "t = [" << fixed(t_m.x(), 5) << ", " << fixed(t_m.y(), 5) << ", " << fixed(t_m.z(), 5)
         << "] m (baseline " << fixed(t_m.norm(), 5) << " m), rotated "
         << fixed(rotation.angle() * kDegPerRad, 4) << " deg.\n"
         << "# Its mount below is that pose with every joint at zero and the left camera's mount\n"
         << "# as the rig gives it. Include it from the rig with `camera_calibration: FILE`.\n";

  YAML::Emitter out;
  out.SetDoublePrecision(kSignificantDigits);
  out << YAML::BeginMap << YAML::Key << "cameras" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << rig.stereo->left_camera << YAML::Value << YAML::BeginMap;
  emit_intrinsics(out, calibration.left);
  out << YAML::EndMap;
  out << YAML::Key << rig.stereo->right_camera << YAML::Value << YAML::BeginMap;
  emit_intrinsics(out, calibration.right);
  emit_mount(out, right_mount);
  out << YAML::EndMap << YAML::EndMap << YAML::EndMap;
  return header.str() + out.c_str() + "\n";
}

std::string rig_camera_mount_yaml(const config::RigConfig& rig, const std::string& camera,
                                  const config::Pose& mount, const std::string& summary,
                                  const CalibrationProvenance& provenance) {
  std::ostringstream header;
  header << "# Camera calibration of rig " << rig.name << ", written by\n#   "
         << provenance.command_line << "\n# " << summary << "\n"
         << "# " << camera << "'s mount measured by hand-eye calibration (" << provenance.board
         << "); the other\n# values as the rig had them. Include it from the rig with "
         << "`camera_calibration: FILE`.\n";
  YAML::Emitter out;
  out.SetDoublePrecision(kSignificantDigits);
  out << YAML::BeginMap << YAML::Key << "cameras" << YAML::Value << YAML::BeginMap;
  for (const config::CameraConfig& entry : rig.cameras) {
    CameraCalibration intrinsics;
    intrinsics.width_px = entry.width_px;
    intrinsics.height_px = entry.height_px;
    intrinsics.focal_x_px = entry.focal_x_px;
    intrinsics.focal_y_px = entry.focal_y_px;
    intrinsics.principal_x_px = entry.principal_x_px;
    intrinsics.principal_y_px = entry.principal_y_px;
    intrinsics.distortion = entry.distortion;
    out << YAML::Key << entry.name << YAML::Value << YAML::BeginMap;
    emit_intrinsics(out, intrinsics);
    emit_mount(out, entry.name == camera ? mount : entry.mount);
    out << YAML::EndMap;
  }
  out << YAML::EndMap << YAML::EndMap;
  return header.str() + out.c_str() + "\n";
}

std::string ros_camera_info_yaml(const std::string& camera_name, const CameraCalibration& camera,
                                 const std::array<double, 9>& rectification,
                                 const std::array<double, 12>& projection) {
  YAML::Emitter out;
  out.SetDoublePrecision(kSignificantDigits);
  out << YAML::BeginMap;
  out << YAML::Key << "image_width" << YAML::Value << camera.width_px;
  out << YAML::Key << "image_height" << YAML::Value << camera.height_px;
  out << YAML::Key << "camera_name" << YAML::Value << camera_name;
  emit_matrix(out, "camera_matrix", 3, 3, camera.camera_matrix());
  out << YAML::Key << "distortion_model" << YAML::Value << "plumb_bob";
  emit_matrix(out, "distortion_coefficients", 1, 5, camera.distortion.opencv_order());
  emit_matrix(out, "rectification_matrix", 3, 3, rectification);
  emit_matrix(out, "projection_matrix", 3, 4, projection);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace cambio::app
