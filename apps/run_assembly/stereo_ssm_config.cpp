#include "stereo_ssm_config.hpp"

#include <iostream>
#include <string>

#include "cambio/perception/perception_config.hpp"
#include "foveation_check.hpp"

namespace cambio::app {

perception::SsmConfig stereo_ssm_config(const config::ExperimentConfig& experiment,
                                        const hal::HardwareInfo& hardware, std::size_t left,
                                        std::size_t right) {
  const std::string ssm_path = experiment.perception_path.empty()
                                   ? perception::default_ssm_config_path()
                                   : experiment.perception_path;
  perception::SsmConfig ssm = perception::load_ssm_config(ssm_path, {});
  if (!(ssm.disparity.scan_range_px > 0.0)) {
    ssm.disparity.scan_range_px = perception::largest_disparity_px(
        hardware.cameras[left].intrinsics.focal_x_px, hardware.stereo->baseline_m);
  }
  for (const std::size_t eye : {left, right}) {
    const config::CameraConfig* camera = experiment.rig.find_camera(hardware.cameras[eye].name);
    if (camera == nullptr) continue;
    for (const std::string& warning : foveation_warnings(*camera, ssm)) {
      std::cerr << "cambio: warning: " << warning << "\n";
    }
  }
  return ssm;
}

}  // namespace cambio::app
