#include "contact_sheet.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <opencv2/imgproc.hpp>

#include "feature_map_image.hpp"
#include "image_files.hpp"

namespace cambio::app {

namespace {

constexpr int kGapPx = 6;
constexpr int kMarginLeftPx = 120;
constexpr int kHeaderPx = 56;
constexpr int kLabelRowsPx = 40;  // Two lines of row labels.

void label(cv::Mat& canvas, const std::string& text, int x, int y, double scale = 0.45) {
  cv::putText(canvas, text, cv::Point(x, y), cv::FONT_HERSHEY_SIMPLEX, scale,
              cv::Scalar(20, 20, 20), 1, cv::LINE_AA);
}

/// The largest w x h box that keeps the aspect of `width` x `height` inside `box_w` x `box_h`,
/// at least 1 px a side.
cv::Size fit_inside(int width, int height, int box_w, int box_h) {
  const double scale =
      std::min(static_cast<double>(box_w) / width, static_cast<double>(box_h) / height);
  return {std::clamp(static_cast<int>(std::floor(width * scale)), 1, box_w),
          std::clamp(static_cast<int>(std::floor(height * scale)), 1, box_h)};
}

/// The maps shown, as indices into the operator bank: intensity, the first sigma's derivatives
/// and Laplacian, Sobel and the average where the bank has them, then any others, nine at most.
std::vector<int> sheet_columns(const perception::SensoryServo& servo) {
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
  return columns;
}

/// Where everything goes on the canvas, px.
struct SheetLayout {
  int retina_w = 0;  ///< A retina level's size, retina px.
  int retina_h = 0;
  int levels = 0;
  int tile_w = 0;
  int tile_h = 0;
  int row_h = 0;
  int grid_w = 0;
  int grid_h = 0;
  int view_box = 0;  ///< The square box each image is fitted into.
  int view_w = 0;
  int view_h = 0;
};

SheetLayout sheet_layout(const perception::SsmConfig& cfg, int column_count,
                         const hal::Image& image) {
  SheetLayout l;
  l.retina_w = cfg.retina.width_px;
  l.retina_h = cfg.retina.height_px;
  l.levels = cfg.retina.levels;
  const int w = l.retina_w;
  const int h = l.retina_h;
  // The images' box is square and as wide as half the grid: at most this tall.
  const int view_box_max = (kSheetMaxWidthPx - 3 * kGapPx) / 2;
  const int grid_max_h = kSheetMaxHeightPx - view_box_max - 40;
  const double zoom = std::max(1, 112 / std::max(w, h));
  const double fit_w =
      static_cast<double>((kSheetMaxWidthPx - kMarginLeftPx) / column_count - kGapPx) / w;
  const double fit_h =
      static_cast<double>((grid_max_h - kHeaderPx - kGapPx) / (2 * l.levels) - kGapPx) / h;
  double scale = std::min({zoom, fit_w, fit_h});
  if (scale >= 1.0) scale = std::floor(scale);
  l.tile_w = std::max(1, static_cast<int>(std::floor(w * scale)));
  l.tile_h = std::max(1, static_cast<int>(std::floor(h * scale)));
  l.row_h = std::max(l.tile_h, kLabelRowsPx);
  l.grid_w = kMarginLeftPx + column_count * (l.tile_w + kGapPx);
  l.grid_h = kHeaderPx + 2 * l.levels * (l.row_h + kGapPx) + kGapPx;
  l.view_box = std::max(1, (l.grid_w - 3 * kGapPx) / 2);
  const cv::Size view = fit_inside(image.width_px, image.height_px, l.view_box, l.view_box);
  l.view_w = view.width;
  l.view_h = view.height;
  return l;
}

/// The title, the maps' names over the columns, and a row of tiles per level of each eye.
void draw_feature_grid(cv::Mat& canvas, const SheetLayout& l, const std::vector<int>& columns,
                       const perception::SensoryServo& servo, const perception::SsmFrame& frame) {
  label(canvas,
        "Cambio SSM: retina levels (rows) and feature maps (columns); signed maps: grey = 0", 8,
        16);
  const auto& maps = servo.operators().maps();
  for (std::size_t c = 0; c < columns.size(); ++c) {
    label(canvas, maps[static_cast<std::size_t>(columns[c])].name,
          kMarginLeftPx + static_cast<int>(c) * (l.tile_w + kGapPx), kHeaderPx - 6, 0.4);
  }
  for (int eye = 0; eye < 2; ++eye) {
    for (int k = 0; k < l.levels; ++k) {
      const int y = kHeaderPx + (eye * l.levels + k) * (l.row_h + kGapPx);
      const auto& g =
          frame.summary.geometry[static_cast<std::size_t>(eye)][static_cast<std::size_t>(k)];
      label(canvas, std::string(eye == 0 ? "left" : "right") + " L" + std::to_string(k), 6, y + 16);
      label(canvas, "block " + std::to_string(g.scale_px) + " px", 6, y + 34, 0.4);
      for (std::size_t c = 0; c < columns.size(); ++c) {
        const cv::Mat tile = feature_map_tile(
            frame.maps[static_cast<std::size_t>(eye)].map(k, columns[c]), l.retina_w, l.retina_h,
            is_signed_map(maps[static_cast<std::size_t>(columns[c])]), l.tile_w, l.tile_h);
        cv::Mat colour;
        cv::cvtColor(tile, colour, cv::COLOR_GRAY2BGR);
        colour.copyTo(canvas(cv::Rect(kMarginLeftPx + static_cast<int>(c) * (l.tile_w + kGapPx), y,
                                      l.tile_w, l.tile_h)));
      }
    }
  }
}

/// Both images under the grid, each level's footprint drawn in a colour of its own.
void draw_footprints(cv::Mat& canvas, const SheetLayout& l, const perception::SsmFrame& frame,
                     const hal::Image& left, const hal::Image& right) {
  const cv::Scalar colours[] = {{0, 0, 255},   {0, 160, 0},   {255, 0, 0}, {0, 160, 255},
                                {200, 0, 200}, {120, 120, 0}, {0, 0, 0},   {90, 90, 90}};
  for (int eye = 0; eye < 2; ++eye) {
    const hal::Image& image = eye == 0 ? left : right;
    const cv::Mat grey(image.height_px, image.width_px, CV_8U,
                       const_cast<std::uint8_t*>(image.pixels.data()));
    cv::Mat small;
    cv::resize(grey, small, cv::Size(l.view_w, l.view_h), 0, 0, cv::INTER_AREA);
    cv::Mat colour;
    cv::cvtColor(small, colour, cv::COLOR_GRAY2BGR);
    const double fx = static_cast<double>(l.view_w) / image.width_px;
    const double fy = static_cast<double>(l.view_h) / image.height_px;
    for (int k = 0; k < l.levels; ++k) {
      const auto& g =
          frame.summary.geometry[static_cast<std::size_t>(eye)][static_cast<std::size_t>(k)];
      cv::rectangle(colour,
                    cv::Rect(static_cast<int>(std::lround(g.origin_x_px * fx)),
                             static_cast<int>(std::lround(g.origin_y_px * fy)),
                             static_cast<int>(std::lround(l.retina_w * g.scale_px * fx)),
                             static_cast<int>(std::lround(l.retina_h * g.scale_px * fy))),
                    colours[k % 8], 1);
    }
    const int x = kGapPx + eye * (l.view_box + kGapPx);
    colour.copyTo(canvas(cv::Rect(x, l.grid_h + 26, l.view_w, l.view_h)));
    label(canvas, std::string(eye == 0 ? "left" : "right") + " image, level footprints", x,
          l.grid_h + 18);
  }
}

/// The disparity at the fovea, under the title.
void draw_disparity_caption(cv::Mat& canvas, const perception::DisparityResult& d) {
  char text[160];
  if (d.valid) {
    std::snprintf(text, sizeof text, "disparity %.2f px (confidence %.2f, level %d)",
                  static_cast<double>(d.disparity_px), static_cast<double>(d.confidence), d.level);
  } else {
    std::snprintf(text, sizeof text, "disparity invalid (no texture or no match)");
  }
  label(canvas, text, 8, 34);
}

}  // namespace

cv::Mat contact_sheet(const perception::SensoryServo& servo, const perception::SsmFrame& frame,
                      const hal::Image& left, const hal::Image& right) {
  const std::vector<int> columns = sheet_columns(servo);
  const SheetLayout layout = sheet_layout(servo.config(), static_cast<int>(columns.size()), left);
  cv::Mat canvas(layout.grid_h + layout.view_h + 40, layout.grid_w, CV_8UC3,
                 cv::Scalar(235, 235, 235));
  draw_feature_grid(canvas, layout, columns, servo, frame);
  draw_footprints(canvas, layout, frame, left, right);
  draw_disparity_caption(canvas, frame.summary.disparity);
  return canvas;
}

std::vector<std::uint8_t> contact_sheet_png(const perception::SensoryServo& servo,
                                            const perception::SsmFrame& frame,
                                            const hal::Image& left, const hal::Image& right) {
  const cv::Mat sheet = contact_sheet(servo, frame, left, right);
  hal::Image png(sheet.cols, sheet.rows, hal::PixelFormat::kRgb8);
  cv::Mat rgb(sheet.rows, sheet.cols, CV_8UC3, png.pixels.data());
  cv::cvtColor(sheet, rgb, cv::COLOR_BGR2RGB);
  return encode_png(png);
}

}  // namespace cambio::app
