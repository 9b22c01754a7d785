#include "foveation_check.hpp"

#include "cambio/perception/sensory_servo.hpp"

namespace cambio::app {

std::vector<std::string> foveation_warnings(const config::CameraConfig& camera,
                                            const perception::SsmConfig& ssm) {
  std::vector<std::string> warnings;
  const config::SimFoveationConfig& foveation = camera.sim_foveation;
  if (!foveation.enabled()) return warnings;
  // The SSM's own retina, so the apron is the one its operators and motion estimator need.
  const perception::SensoryServo servo(ssm, camera.width_px, camera.height_px);
  const perception::Retina& retina = servo.retina(hal::Eye::kLeft);
  const perception::PixelPoint centre{camera.width_px / 2, camera.height_px / 2};
  for (int k = 0; k < retina.levels(); ++k) {
    const int scale = retina.scale_of(k, camera.width_px, camera.height_px, centre);
    if (scale >= foveation.periphery_downscale) continue;
    const int extent_x = (retina.width() + 2 * retina.apron()) * scale;
    const int extent_y = (retina.height() + 2 * retina.apron()) * scale;
    if (extent_x <= foveation.fovea_px && extent_y <= foveation.fovea_px) continue;
    warnings.push_back("cameras." + camera.name + ".sim_foveation.fovea_px " +
                       std::to_string(foveation.fovea_px) + " is smaller than retina level " +
                       std::to_string(k) + " (" + std::to_string(scale) + " px blocks, " +
                       std::to_string(extent_x) + "x" + std::to_string(extent_y) +
                       " px with its apron), finer than the periphery's " +
                       std::to_string(foveation.periphery_downscale) +
                       " px: it reads upsampled periphery beyond the fovea");
  }
  return warnings;
}

}  // namespace cambio::app
