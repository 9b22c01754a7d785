#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include "cambio/config/camera_calibration.hpp"
#include "format.hpp"

namespace cambio::config {

namespace {

// Radial terms of real plumb-bob fits stay within units (wide lenses reach tens in k3);
// tangential ones are a decentring of a fraction of a percent. Beyond these a value is a typo, or
// a fisheye lens, which needs another model.
constexpr double kMaxRadialTerm = 1000.0;
constexpr double kMaxTangentialTerm = 1.0;
// A camera's mount on its link: within the robot.
constexpr double kMaxMountOffset_m = 10.0;

std::vector<std::string> camera_names(const RigConfig& rig) {
  std::vector<std::string> names;
  for (const auto& camera : rig.cameras) names.push_back(camera.name);
  return names;
}

/// Size must match: intrinsics and distortion hold for the resolution they were measured at.
void check_size(MapReader& r, const CameraConfig& camera) {
  const Range side = Range::closed(1, 1e9);
  const auto width_px = r.integer("width_px", side);
  const auto height_px = r.integer("height_px", side);
  for (const auto& [key, found, expected] :
       {std::tuple{"width_px", width_px, camera.width_px},
        std::tuple{"height_px", height_px, camera.height_px}}) {
    if (r.has(key) && found != expected) {
      r.error(key, "expected the rig's " + std::to_string(expected) + " for camera " +
                       in_quotes(camera.name) +
                       " (a calibration holds for the resolution it was made at), found " +
                       std::to_string(found));
    }
  }
}

void read_principal_point(MapReader& r, CameraConfig& camera) {
  const auto point = r.numbers("principal_point_px");
  if (!r.has("principal_point_px")) return;
  if (point.size() != 2) {
    r.error("principal_point_px", "expected a list of 2 numbers [cx, cy], found a list of " +
                                      std::to_string(point.size()));
    return;
  }
  const bool inside = point[0] >= -0.5 && point[0] <= camera.width_px - 0.5 && point[1] >= -0.5 &&
                      point[1] <= camera.height_px - 0.5;
  if (!inside) {
    r.error("principal_point_px", "expected a point inside the " + std::to_string(camera.width_px) +
                                      "x" + std::to_string(camera.height_px) + " image, found [" +
                                      format_number(point[0]) + ", " + format_number(point[1]) +
                                      "]");
    return;
  }
  camera.principal_x_px = point[0];
  camera.principal_y_px = point[1];
}

void apply_camera_entry(MapReader& r, CameraConfig& camera) {
  check_size(r, camera);
  camera.focal_x_px = r.number("focal_x_px", Range::positive());
  camera.focal_y_px = r.number("focal_y_px", Range::positive());
  read_principal_point(r, camera);
  MapReader distortion = r.map("distortion");
  camera.distortion = read_plumb_bob_distortion(distortion);
  if (r.has("origin_xyz_m")) {
    camera.mount.xyz_m =
        r.vector3("origin_xyz_m", Range::closed(-kMaxMountOffset_m, kMaxMountOffset_m));
  }
  camera.mount.rpy_rad = r.angles3_rad_or("origin_rpy", camera.mount.rpy_rad);
  r.finish();
}

}  // namespace

hal::PlumbBobDistortion read_plumb_bob_distortion(MapReader& r) {
  const Range radial = Range::closed(-kMaxRadialTerm, kMaxRadialTerm)
                           .because("a plumb-bob lens; a fisheye needs another model");
  const Range tangential = Range::closed(-kMaxTangentialTerm, kMaxTangentialTerm)
                               .because("a lens decentred by a fraction of a percent");
  hal::PlumbBobDistortion distortion;
  distortion.k1 = r.number("k1", radial);
  distortion.k2 = r.number("k2", radial);
  distortion.p1 = r.number("p1", tangential);
  distortion.p2 = r.number("p2", tangential);
  distortion.k3 = r.number("k3", radial);
  r.finish();
  return distortion;
}

void read_camera_calibration_key(MapReader& root, RigConfig& rig) {
  const std::string key(kCameraCalibrationKey);
  if (!root.has(key)) return;
  const std::string named = root.text(key);
  if (named.empty()) return;
  // Relative to the rig file, as an included file is wherever includes exist (C, xacro).
  const std::filesystem::path path = std::filesystem::path(named).is_absolute()
                                         ? std::filesystem::path(named)
                                         : std::filesystem::path(root.file()).parent_path() / named;
  if (const auto problem = config_file_problem(path.string())) {
    root.error(key,
               "cannot read the camera calibration " + in_quotes(path.string()) + ": " + *problem);
    return;
  }
  try {
    ConfigDocument document = ConfigDocument::load_file(path.string());
    MapReader calibration = document.root();
    const std::vector<std::string> known = camera_names(rig);
    if (!calibration.has("cameras")) {
      calibration.error("cameras", "missing key (expected a map of the rig's cameras by name)");
    }
    for (auto& [name, entry] : calibration.named_maps("cameras")) {
      CameraConfig* camera = nullptr;
      for (auto& candidate : rig.cameras) {
        if (candidate.name == name) camera = &candidate;
      }
      if (camera == nullptr) {
        std::string message = "expected a camera of rig " + in_quotes(rig.name) + " (" +
                              join(known) + "), found " + in_quotes(name);
        if (const auto suggestion = closest_name(name, known)) {
          message += "; did you mean " + in_quotes(*suggestion) + "?";
        }
        entry.error("", message);
        continue;
      }
      apply_camera_entry(entry, *camera);
    }
    calibration.finish();
    for (const auto& issue : document.issues()->issues()) root.issues()->add(issue);
  } catch (const ConfigError& error) {
    for (const auto& issue : error.issues()) root.issues()->add(issue);
  }
}

}  // namespace cambio::config
