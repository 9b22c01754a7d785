// `cambio perceive`: run the Sensory Servo Module once on an image pair and write what it saw:
// result.json (disparity and confidence at the fovea, per-level estimates, moments, timings)
// and contact_sheet.png (the retina levels and feature maps of both eyes, and where each level
// lies in the images).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

#include "argument_parser.hpp"
#include "cambio/config/config_error.hpp"
#include "cambio/config/map_reader.hpp"
#include "cambio/perception/sensory_servo.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "feature_map_image.hpp"
#include "image_files.hpp"
#include "json_output.hpp"
#include "output_directory.hpp"

namespace cambio::app {

namespace {

perception::PixelPoint parse_point(const std::string& option, const std::string& text) {
  const std::size_t comma = text.find(',');
  try {
    if (comma == std::string::npos) throw std::invalid_argument("no comma");
    std::size_t used_x = 0;
    std::size_t used_y = 0;
    const int x = std::stoi(text.substr(0, comma), &used_x);
    const std::string y_text = text.substr(comma + 1);
    const int y = std::stoi(y_text, &used_y);
    if (used_x != comma || used_y != y_text.size()) throw std::invalid_argument("trailing text");
    return {x, y};
  } catch (const std::exception&) {
    throw UsageError("perceive: --" + option + " expects X,Y in pixels (e.g. 320,240), found '" +
                     text + "'");
  }
}

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

void label(cv::Mat& canvas, const std::string& text, int x, int y, double scale = 0.45) {
  cv::putText(canvas, text, cv::Point(x, y), cv::FONT_HERSHEY_SIMPLEX, scale,
              cv::Scalar(20, 20, 20), 1, cv::LINE_AA);
}

/// The contact sheet is a picture for people: whatever the retina's size and the images' shape,
/// it fits this canvas (a 1x500 image once made it 1182x292046 px, 1 GB of pixels).
constexpr int kSheetMaxWidthPx = 1600;
constexpr int kSheetMaxHeightPx = 2400;

/// The largest w x h box that keeps the aspect of `width` x `height` inside `box_w` x `box_h`,
/// at least 1 px a side.
cv::Size fit_inside(int width, int height, int box_w, int box_h) {
  const double scale =
      std::min(static_cast<double>(box_w) / width, static_cast<double>(box_h) / height);
  return {std::clamp(static_cast<int>(std::floor(width * scale)), 1, box_w),
          std::clamp(static_cast<int>(std::floor(height * scale)), 1, box_h)};
}

/// Columns: intensity and up to eight feature maps; rows: each level of each eye. Beneath, both
/// images with each level's footprint drawn (the paper's Figure 1, bottom). Tiles are enlarged
/// to about 112 px by whole pixels and shrunk when the grid would not fit kSheetMaxWidthPx x
/// kSheetMaxHeightPx; the images are fitted into a square box under the grid.
cv::Mat contact_sheet(const perception::SensoryServo& servo, const perception::SsmFrame& frame,
                      const hal::Image& left, const hal::Image& right) {
  const auto& cfg = servo.config();
  const int w = cfg.retina.width_px;
  const int h = cfg.retina.height_px;
  std::vector<int> columns{0};
  const std::string s0 =
      servo.operators().maps().size() > 1 ? servo.operators().maps()[1].name.substr(4) : "";
  for (const std::string& name :
       {"g1x@" + s0, "g1y@" + s0, "g2x@" + s0, "g2y@" + s0, "log@" + s0, std::string("sobel_x"),
        std::string("sobel_y"), std::string("average")}) {
    const int index = servo.operators().find(name);
    if (index > 0) columns.push_back(index);
  }
  for (int i = 1; i < servo.operators().map_count() && columns.size() < 9; ++i) {
    if (std::find(columns.begin(), columns.end(), i) == columns.end()) columns.push_back(i);
  }
  const int gap = 6;
  const int margin_left = 120;
  const int header = 56;
  const int label_rows_px = 40;  // Two lines of row labels.
  const int levels = cfg.retina.levels;
  const int column_count = static_cast<int>(columns.size());
  // The images' box is square and as wide as half the grid: at most this tall.
  const int view_box_max = (kSheetMaxWidthPx - 3 * gap) / 2;
  const int grid_max_h = kSheetMaxHeightPx - view_box_max - 40;
  const double zoom = std::max(1, 112 / std::max(w, h));
  const double fit_w =
      static_cast<double>((kSheetMaxWidthPx - margin_left) / column_count - gap) / w;
  const double fit_h = static_cast<double>((grid_max_h - header - gap) / (2 * levels) - gap) / h;
  double scale = std::min({zoom, fit_w, fit_h});
  if (scale >= 1.0) scale = std::floor(scale);
  const int tile_w = std::max(1, static_cast<int>(std::floor(w * scale)));
  const int tile_h = std::max(1, static_cast<int>(std::floor(h * scale)));
  const int row_h = std::max(tile_h, label_rows_px);
  const int grid_w = margin_left + column_count * (tile_w + gap);
  const int grid_h = header + 2 * levels * (row_h + gap) + gap;
  const int view_box = std::max(1, (grid_w - 3 * gap) / 2);
  const cv::Size view = fit_inside(left.width_px, left.height_px, view_box, view_box);
  const int view_w = view.width;
  const int view_h = view.height;
  cv::Mat canvas(grid_h + view_h + 40, grid_w, CV_8UC3, cv::Scalar(235, 235, 235));
  label(canvas,
        "Cambio SSM: retina levels (rows) and feature maps (columns); signed maps: grey = 0", 8,
        16);
  for (std::size_t c = 0; c < columns.size(); ++c) {
    label(canvas, servo.operators().maps()[static_cast<std::size_t>(columns[c])].name,
          margin_left + static_cast<int>(c) * (tile_w + gap), header - 6, 0.4);
  }
  for (int eye = 0; eye < 2; ++eye) {
    for (int k = 0; k < levels; ++k) {
      const int y = header + (eye * levels + k) * (row_h + gap);
      const auto& g =
          frame.summary.geometry[static_cast<std::size_t>(eye)][static_cast<std::size_t>(k)];
      label(canvas, std::string(eye == 0 ? "left" : "right") + " L" + std::to_string(k), 6, y + 16);
      label(canvas, "block " + std::to_string(g.scale_px) + " px", 6, y + 34, 0.4);
      for (std::size_t c = 0; c < columns.size(); ++c) {
        const cv::Mat tile = feature_map_tile(
            frame.maps[static_cast<std::size_t>(eye)].map(k, columns[c]), w, h,
            is_signed_map(servo.operators().maps()[static_cast<std::size_t>(columns[c])]), tile_w,
            tile_h);
        cv::Mat colour;
        cv::cvtColor(tile, colour, cv::COLOR_GRAY2BGR);
        colour.copyTo(canvas(
            cv::Rect(margin_left + static_cast<int>(c) * (tile_w + gap), y, tile_w, tile_h)));
      }
    }
  }
  const cv::Scalar colours[] = {{0, 0, 255},   {0, 160, 0},   {255, 0, 0}, {0, 160, 255},
                                {200, 0, 200}, {120, 120, 0}, {0, 0, 0},   {90, 90, 90}};
  for (int eye = 0; eye < 2; ++eye) {
    const hal::Image& image = eye == 0 ? left : right;
    const cv::Mat grey(image.height_px, image.width_px, CV_8U,
                       const_cast<std::uint8_t*>(image.pixels.data()));
    cv::Mat small;
    cv::resize(grey, small, cv::Size(view_w, view_h), 0, 0, cv::INTER_AREA);
    cv::Mat colour;
    cv::cvtColor(small, colour, cv::COLOR_GRAY2BGR);
    const double fx = static_cast<double>(view_w) / image.width_px;
    const double fy = static_cast<double>(view_h) / image.height_px;
    for (int k = 0; k < levels; ++k) {
      const auto& g =
          frame.summary.geometry[static_cast<std::size_t>(eye)][static_cast<std::size_t>(k)];
      cv::rectangle(colour,
                    cv::Rect(static_cast<int>(std::lround(g.origin_x_px * fx)),
                             static_cast<int>(std::lround(g.origin_y_px * fy)),
                             static_cast<int>(std::lround(w * g.scale_px * fx)),
                             static_cast<int>(std::lround(h * g.scale_px * fy))),
                    colours[k % 8], 1);
    }
    const int x = gap + eye * (view_box + gap);
    colour.copyTo(canvas(cv::Rect(x, grid_h + 26, view_w, view_h)));
    label(canvas, std::string(eye == 0 ? "left" : "right") + " image, level footprints", x,
          grid_h + 18);
  }
  const auto& d = frame.summary.disparity;
  char text[160];
  if (d.valid) {
    std::snprintf(text, sizeof text, "disparity %.2f px (confidence %.2f, level %d)",
                  static_cast<double>(d.disparity_px), static_cast<double>(d.confidence), d.level);
  } else {
    std::snprintf(text, sizeof text, "disparity invalid (no texture or no match)");
  }
  label(canvas, text, 8, 34);
  return canvas;
}

}  // namespace

int run_perceive_command(std::span<const std::string> args) {
  ArgumentParser parser("perceive",
                        "--left L.png --right R.png [--fixation X,Y | --fixation-left X,Y "
                        "--fixation-right X,Y] [--config FILE] [--set key=value]... --out DIR");
  parser.option("left", "FILE", "left image (PNG, JPEG, PGM or PPM, grey or colour, 8 or 16 bit)")
      .option("right", "FILE", "right image, same size as the left")
      .option("fixation", "X,Y", "both retinas' fixation pixel (default: the image centre)")
      .option("fixation-left", "X,Y", "the left retina's fixation pixel")
      .option("fixation-right", "X,Y", "the right retina's fixation pixel")
      .option("config", "FILE", "SSM config (default: firmware_config/perception/ssm.yaml)")
      .repeated_option("set", "KEY=VALUE", "override a config value, e.g. retina.width_px=64")
      .option("out", "DIR", "where result.json and contact_sheet.png go (created)");
  if (!parser.parse(args)) return kExitOk;
  for (const char* required : {"left", "right", "out"}) {
    if (!parser.has(required))
      throw UsageError(std::string("perceive: --") + required + " is required");
  }
  // Before any work: a run that cannot write its results is refused at once.
  // Checked and claimed before the work: a bad destination fails at once.
  OutputDirectory out(parser.value("out"), "perceive");
  if (parser.has("fixation") && (parser.has("fixation-left") || parser.has("fixation-right"))) {
    throw UsageError("perceive: give --fixation or --fixation-left/--fixation-right, not both");
  }
  if (parser.has("fixation-left") != parser.has("fixation-right")) {
    throw UsageError("perceive: --fixation-left and --fixation-right go together");
  }

  perception::SsmConfig config;
  std::string config_path = parser.value("config", perception::default_ssm_config_path());
  try {
    std::vector<config::ConfigOverride> overrides;
    for (const auto& text : parser.values("set")) overrides.push_back(config::parse_override(text));
    if (!config_path.empty()) config = perception::load_ssm_config(config_path, overrides);
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }

  // OpenCV logs a warning of its own for an image it cannot decode; decode_image's message names
  // the file and says why, so only OpenCV's errors are let through.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
  hal::Image left;
  hal::Image right;
  try {
    left = read_image_file(parser.value("left"), hal::PixelFormat::kGrey8);
    right = read_image_file(parser.value("right"), hal::PixelFormat::kGrey8);
  } catch (const ImageFileError& error) {
    std::cerr << "cambio perceive: " << error.what() << "\n";
    return kExitBadInput;
  }
  if (left.width_px != right.width_px || left.height_px != right.height_px) {
    std::cerr << "cambio perceive: the images differ in size: " << parser.value("left") << " is "
              << left.width_px << "x" << left.height_px << ", " << parser.value("right") << " is "
              << right.width_px << "x" << right.height_px << "\n";
    return kExitBadInput;
  }
  perception::PixelPoint fixation_left{left.width_px / 2, left.height_px / 2};
  perception::PixelPoint fixation_right = fixation_left;
  if (parser.has("fixation")) {
    fixation_left = fixation_right = parse_point("fixation", parser.value("fixation"));
  } else if (parser.has("fixation-left")) {
    fixation_left = parse_point("fixation-left", parser.value("fixation-left"));
    fixation_right = parse_point("fixation-right", parser.value("fixation-right"));
  }
  for (const auto& [name, p] :
       {std::pair{"left", fixation_left}, std::pair{"right", fixation_right}}) {
    if (p.x < 0 || p.y < 0 || p.x >= left.width_px || p.y >= left.height_px) {
      std::cerr << "cambio perceive: the " << name << " fixation " << p.x << "," << p.y
                << " is outside the " << left.width_px << "x" << left.height_px << " image\n";
      return kExitBadInput;
    }
  }

  std::optional<perception::SensoryServo> servo;
  try {
    servo.emplace(config, left.width_px, left.height_px);
  } catch (const std::invalid_argument& error) {
    std::cerr << "cambio perceive: inconsistent SSM config: " << error.what() << "\n";
    return kExitBadInput;
  }
  // Where the images are smaller than the finest retina level with the apron its kernels read,
  // every level samples the images' clamped borders, not the scene.
  const int apron = servo->retina(hal::Eye::kLeft).apron();
  const int min_width = config.retina.width_px + 2 * apron;
  const int min_height = config.retina.height_px + 2 * apron;
  if (left.width_px < min_width || left.height_px < min_height) {
    std::cerr << "cambio perceive: " << parser.value("left") << " and " << parser.value("right")
              << " are " << left.width_px << "x" << left.height_px
              << " px; the SSM needs images of at least " << min_width << "x" << min_height
              << " px (its finest retina level, " << config.retina.width_px << "x"
              << config.retina.height_px << " px, with the " << apron
              << " px its kernels read around it)\n";
    return kExitBadInput;
  }
  perception::SsmFrame frame = servo->make_frame();
  perception::FeatureRequest request;
  request.motion = false;  // One frame per eye: there is no previous frame to move from.
  if (servo->process(left, right, fixation_left, fixation_right, request, frame) !=
      hal::Status::kOk) {
    std::cerr << "cambio perceive: the SSM rejected the images\n";
    return kExitFailure;
  }

  const perception::SsmSummary& s = frame.summary;
  const auto& d = s.disparity;
  Json levels = Json::array();
  for (int k = 0; k < s.levels; ++k) levels.push_back(level_json(s, k, config.moments.map));
  Json maps = Json::array();
  for (const auto& map : servo->operators().maps()) maps.push_back(map.name);
  const Json result = {
      {"left", parser.value("left")},
      {"right", parser.value("right")},
      {"config", config_path},
      {"image_size_px", Json::array({left.width_px, left.height_px})},
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
        {"apron_px", servo->retina(hal::Eye::kLeft).apron()}}},
      {"levels", levels},
      {"maps", maps},
      {"timings_us",
       {{"retina", six_digits(s.timings.retina_us)},
        {"features", six_digits(s.timings.features_us)},
        {"disparity", six_digits(s.timings.disparity_us)},
        {"moments", six_digits(s.timings.moments_us)},
        {"total", six_digits(s.timings.total_us)}}},
      {"contact_sheet", "contact_sheet.png"}};
  out.stage("result.json", json_text(result));

  const cv::Mat sheet = contact_sheet(*servo, frame, left, right);
  hal::Image png(sheet.cols, sheet.rows, hal::PixelFormat::kRgb8);
  cv::Mat rgb(sheet.rows, sheet.cols, CV_8UC3, png.pixels.data());
  cv::cvtColor(sheet, rgb, cv::COLOR_BGR2RGB);
  out.stage("contact_sheet.png", encode_png(png));
  out.commit();

  char disparity_text[32] = "invalid";
  if (d.valid) {
    std::snprintf(disparity_text, sizeof disparity_text, "%.6g",
                  static_cast<double>(d.disparity_px));
  }
  std::printf("disparity %s px, confidence %.2f (level %d); wrote %s and %s\n", disparity_text,
              static_cast<double>(d.confidence), d.level, (out.path() / "result.json").c_str(),
              (out.path() / "contact_sheet.png").c_str());
  return kExitOk;
}

}  // namespace cambio::app
