#include "perceive_result.hpp"

#include <string>

namespace cambio::app {

namespace {

/// A measured value in result.json: six significant digits (null when not finite).
double six_digits(double value) {
  return as_printed(value, "%.6g");
}

/// A disparity in result.json: null when the estimate is not valid.
Json disparity_or_null(bool valid, double disparity_px) {
  return valid ? Json(six_digits(disparity_px)) : Json(nullptr);
}

Json moments_json(const perception::Moments& m) {
  if (!m.valid) return {{"valid", false}};
  return {{"valid", true},
          {"area_px2", six_digits(m.area_px2)},
          {"centroid_px", Json::array({six_digits(m.centroid_x_px), six_digits(m.centroid_y_px)})},
          {"mu20_px2", six_digits(m.mu20_px2)},
          {"mu02_px2", six_digits(m.mu02_px2)},
          {"mu11_px2", six_digits(m.mu11_px2)},
          {"orientation_rad", six_digits(m.orientation_rad)},
          {"eccentricity", six_digits(m.eccentricity)}};
}

/// One entry of result.json's "levels": the level's footprint, disparity and moments.
Json level_json(const perception::SsmSummary& s, int k, const std::string& moments_map) {
  const auto level = static_cast<std::size_t>(k);
  const auto& l = s.disparity.per_level[level];
  const auto& g = s.geometry[0][level];
  const Json disparity = {{"searched", l.searched},
                          {"valid", l.valid},
                          {"disparity_px", disparity_or_null(l.valid, l.disparity_px)},
                          {"confidence", six_digits(l.confidence)},
                          {"peak_score", six_digits(l.peak_score)},
                          {"texture_rms", six_digits(l.texture_rms)},
                          {"at_range_edge", l.at_range_edge},
                          {"aperture", l.aperture},
                          {"x_structure", six_digits(l.x_structure)},
                          {"search_level_px", Json::array({l.search_min_px, l.search_max_px})},
                          {"moved_windows", l.moved_windows}};
  const Json moments = {{"map", moments_map},
                        {"left", moments_json(s.moments[0][level])},
                        {"right", moments_json(s.moments[1][level])}};
  return {{"level", k},
          {"scale_px", g.scale_px},
          {"origin_left_px", Json::array({g.origin_x_px, g.origin_y_px})},
          {"fraction_inside_left", six_digits(g.fraction_inside)},
          {"disparity", disparity},
          {"moments", moments}};
}

}  // namespace

Json perceive_result_json(const PerceiveInputs& inputs, const perception::SensoryServo& servo,
                          const perception::SsmSummary& summary) {
  const perception::SsmSummary& s = summary;
  const auto& d = s.disparity;
  const perception::SsmConfig& config = inputs.config;
  const perception::PixelPoint& fixation_left = inputs.fixation_left;
  const perception::PixelPoint& fixation_right = inputs.fixation_right;
  Json levels = Json::array();
  for (int k = 0; k < s.levels; ++k) levels.push_back(level_json(s, k, config.moments.map));
  Json maps = Json::array();
  for (const auto& map : servo.operators().maps()) maps.push_back(map.name);
  const perception::DisparityScanResult& scan = servo.last_scan();
  Json scan_json = nullptr;
  if (scan.searched) {
    Json candidates = Json::array();
    for (int i = 0; i < scan.count; ++i) {
      const perception::DisparityCandidate& c = scan.candidates[static_cast<std::size_t>(i)];
      candidates.push_back({{"disparity_px", six_digits(c.disparity_px)},
                            {"score", six_digits(c.score)},
                            {"context_score", six_digits(c.context_score)}});
    }
    scan_json = {{"level", scan.level},
                 {"scale_px", scan.scale_px},
                 {"window_tier", scan.window_tier},
                 {"window_samples", scan.window_samples},
                 {"localized", scan.localized},
                 {"texture_rms", six_digits(scan.texture_rms)},
                 {"candidates", candidates}};
  }
  return {{"left", inputs.left_path},
          {"right", inputs.right_path},
          {"config", inputs.config_path},
          {"image_size_px", Json::array({inputs.left.width_px, inputs.left.height_px})},
          {"fixation_left_px", Json::array({fixation_left.x, fixation_left.y})},
          {"fixation_right_px", Json::array({fixation_right.x, fixation_right.y})},
          {"convention",
           "disparity_px = x_left - x_right in level-0 px, each relative to its retina's fixation "
           "(the vergence error); image_disparity_px adds the fixation offset"},
          {"disparity_px", disparity_or_null(d.valid, d.disparity_px)},
          {"confidence", six_digits(d.confidence)},
          {"disparity_valid", d.valid},
          {"disparity_level", d.level},
          {"image_disparity_px",
           disparity_or_null(d.valid, d.disparity_px + (fixation_left.x - fixation_right.x))},
          {"retina",
           {{"levels", config.retina.levels},
            {"width_px", config.retina.width_px},
            {"height_px", config.retina.height_px},
            {"apron_px", servo.retina(hal::Eye::kLeft).apron()}}},
          {"scan", scan_json},
          {"levels", levels},
          {"maps", maps},
          {"timings_us",
           {{"retina", six_digits(s.timings.retina_us)},
            {"features", six_digits(s.timings.features_us)},
            {"disparity", six_digits(s.timings.disparity_us)},
            {"moments", six_digits(s.timings.moments_us)},
            {"total", six_digits(s.timings.total_us)}}},
          {"contact_sheet", "contact_sheet.png"}};
}

}  // namespace cambio::app
