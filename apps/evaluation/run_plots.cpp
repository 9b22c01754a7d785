#include "run_plots.hpp"

#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <system_error>

#include <plplot.h>

#include "output_directory.hpp"

namespace cambio::app {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr PLINT kWidthPx = 1200;
constexpr PLINT kPanelHeightPx = 330;

// Colour map 0 entries set in draw_png().
enum Colour : PLINT { kBlack = 1, kRed = 2, kBlue = 3, kGreen = 4, kOrange = 5 };

struct Series {
  std::string label;
  Colour colour = kBlack;
  PLINT line_style = 1;   ///< PLplot's pllsty: 1 solid, 2 dashed...
  std::vector<double> y;  ///< One per x; NaN leaves a gap.
};

struct Panel {
  std::string y_label;
  std::vector<Series> series;
};

struct Figure {
  std::string file;
  std::string title;
  std::vector<double> x;
  std::string x_label = "time (s)";
  std::vector<Panel> panels;
};

struct Range {
  double low = 0.0, high = 1.0;
};

Range range_of(const std::vector<double>& values) {
  double low = INFINITY, high = -INFINITY;
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    low = std::min(low, v);
    high = std::max(high, v);
  }
  if (!(low <= high)) return {};
  if (high - low < 1e-9 * std::max(1.0, std::abs(high))) {
    const double pad = std::max(0.5, 0.1 * std::abs(high));
    return {low - pad, high + pad};
  }
  const double pad = 0.05 * (high - low);
  return {low - pad, high + pad};
}

/// PLplot reports what plabort() refused through plsError's buffer, and cannot recover from
/// plexit() (it calls exit()): everything that could reach plexit (an unknown device, an
/// unwritable file) is checked before plinit().
class PlotSession {
 public:
  PlotSession(const std::string& name, const std::filesystem::path& path, PLINT panels)
      : name_(name) {
    require_device("pngcairo");
    plsError(&code_, message_);
    plsdev("pngcairo");
    plsfnam(path.c_str());
    plspage(0.0, 0.0, kWidthPx, kPanelHeightPx * panels + 60, 0, 0);
    plscolbg(255, 255, 255);
    plssub(1, panels);
    plinit();
    initialised_ = true;
    check("plinit");
    plscol0(kBlack, 0, 0, 0);
    plscol0(kRed, 200, 30, 30);
    plscol0(kBlue, 30, 80, 200);
    plscol0(kGreen, 30, 150, 60);
    plscol0(kOrange, 230, 140, 0);
    check("colours");
  }
  ~PlotSession() {
    if (initialised_) plend();
  }
  PlotSession(const PlotSession&) = delete;
  PlotSession& operator=(const PlotSession&) = delete;

  /// Writes the file (cairo flushes it when the stream ends).
  void finish() {
    plend();
    initialised_ = false;
  }

  void check(const char* step) const {
    if (code_ != 0) {
      throw OutputError(name_ + ": PLplot failed in " + step + ": " + std::string(message_));
    }
  }

 private:
  void require_device(const char* device) const {
    const char* menus[128];
    const char* devices[128];
    const char** menu_list = menus;
    const char** device_list = devices;
    int count = 128;
    plgDevs(&menu_list, &device_list, &count);
    for (int i = 0; i < count; ++i) {
      if (std::string(device_list[i]) == device) return;
    }
    throw OutputError(name_ + ": PLplot has no '" + device + "' device (plplot-driver-cairo)");
  }

  std::string name_;
  PLINT code_ = 0;
  char message_[1024] = {};
  bool initialised_ = false;
};

void draw_panel(PlotSession& session, const Figure& figure, const Panel& panel, bool first) {
  const Range x = range_of(figure.x);
  std::vector<double> all;
  for (const Series& series : panel.series) all.insert(all.end(), series.y.begin(), series.y.end());
  const Range y = range_of(all);
  pladv(0);
  plvpor(0.08, 0.97, 0.16, 0.82);
  plwind(x.low, x.high, y.low, y.high);
  plcol0(kBlack);
  plschr(0.0, 0.9);
  plbox("bcnstg", 0.0, 0, "bcnstvg", 0.0, 0);
  pllab(figure.x_label.c_str(), panel.y_label.c_str(), "");
  if (first) plmtex("t", 2.6, 0.0, 0.0, figure.title.c_str());
  session.check("axes");
  for (std::size_t s = 0; s < panel.series.size(); ++s) {
    const Series& series = panel.series[s];
    plcol0(series.colour);
    pllsty(series.line_style);
    plwidth(1.5);
    // Finite runs only: a NaN (no measurement) leaves a gap.
    std::size_t k = 0;
    const std::size_t n = std::min(series.y.size(), figure.x.size());
    while (k < n) {
      while (k < n && !std::isfinite(series.y[k])) ++k;
      const std::size_t begin = k;
      while (k < n && std::isfinite(series.y[k])) ++k;
      if (k - begin >= 2) {
        plline(static_cast<PLINT>(k - begin), figure.x.data() + begin, series.y.data() + begin);
      } else if (k - begin == 1) {
        plsym(1, figure.x.data() + begin, series.y.data() + begin, 210);
      }
    }
    pllsty(1);
    plmtex("t", 0.8, 0.02 + 0.24 * static_cast<double>(s), 0.0, series.label.c_str());
    session.check(series.label.c_str());
  }
}

std::vector<std::uint8_t> draw_png(const Figure& figure) {
  std::string pattern = (std::filesystem::temp_directory_path() / "cambio-plot-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) {
    throw OutputError(figure.file + ": cannot make a temporary directory for PLplot: " +
                      std::generic_category().message(errno));
  }
  const std::filesystem::path directory(pattern);
  struct RemoveDirectory {
    std::filesystem::path path;
    ~RemoveDirectory() {
      std::error_code ignored;
      std::filesystem::remove_all(path, ignored);
    }
  } remove{directory};
  const std::filesystem::path path = directory / figure.file;
  {
    PlotSession session(figure.file, path, static_cast<PLINT>(figure.panels.size()));
    for (std::size_t p = 0; p < figure.panels.size(); ++p) {
      draw_panel(session, figure, figure.panels[p], p == 0);
    }
    session.finish();
  }
  std::ifstream file(path, std::ios::binary);
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(file)),
                                  std::istreambuf_iterator<char>());
  if (!file.good() && !file.eof()) throw OutputError(figure.file + ": cannot read PLplot's file");
  if (bytes.size() < 8) throw OutputError(figure.file + ": PLplot wrote no image");
  return bytes;
}

Figure gaze_figure(const Trace& trace, const PlotInputs& inputs) {
  Figure figure;
  figure.file = "plot_gaze.png";
  figure.title = inputs.title + ": disparity and true gaze error";
  Series disparity{"disparity (valid)", kBlue, 1, {}};
  Series dominant{"dominant eye", kRed, 1, {}};
  Series verging{"verging eye", kBlue, 1, {}};
  Series occluded{"target occluded", kOrange, 1, {}};
  for (const TraceRow& row : trace.rows) {
    figure.x.push_back(row.time_s);
    disparity.y.push_back(row.disparity_valid ? row.disparity_px : NAN);
    dominant.y.push_back(row.dominant_gaze_error_deg);
    verging.y.push_back(row.verging_gaze_error_deg);
    // Drawn at zero error while the target is hidden: when the verging error is not scored.
    occluded.y.push_back(row.target_occluded ? 0.0 : NAN);
  }
  figure.panels.push_back({"disparity (px)", {disparity}});
  figure.panels.push_back({"true gaze error (deg)", {dominant, verging, occluded}});
  return figure;
}

Figure joints_figure(const Trace& trace, const PlotInputs& inputs) {
  std::vector<std::size_t> joints;
  if (!inputs.joints.empty()) {
    for (const std::string& name : inputs.joints) {
      const auto it = std::find(trace.joint_names.begin(), trace.joint_names.end(), name);
      if (it == trace.joint_names.end()) {
        throw OutputError("plot_joints.png: no joint '" + name + "' in the trace");
      }
      joints.push_back(static_cast<std::size_t>(it - trace.joint_names.begin()));
    }
  } else {
    for (std::size_t j = 0; j < trace.joint_count() && joints.size() < 6; ++j) {
      double low = INFINITY, high = -INFINITY;
      for (std::size_t r = 0; r < trace.rows.size(); ++r) {
        const double v = trace.joints_at(r)[j].true_rad;
        if (!std::isfinite(v)) continue;
        low = std::min(low, v);
        high = std::max(high, v);
      }
      if (high - low > 1e-6) joints.push_back(j);
    }
  }
  Figure figure;
  figure.file = "plot_joints.png";
  figure.title = inputs.title + ": joint angles";
  for (const TraceRow& row : trace.rows) figure.x.push_back(row.time_s);
  for (const std::size_t j : joints) {
    Series command{"command", kRed, 2, {}};
    Series believed{"believed", kBlue, 1, {}};
    Series truth{"true", kBlack, 1, {}};
    for (std::size_t r = 0; r < trace.rows.size(); ++r) {
      const TraceJointSample& sample = trace.joints_at(r)[j];
      command.y.push_back(sample.command_rad * kDegPerRad);
      believed.y.push_back(sample.believed_rad * kDegPerRad);
      truth.y.push_back(sample.true_rad * kDegPerRad);
    }
    figure.panels.push_back({trace.joint_names[j] + " (deg)", {command, believed, truth}});
  }
  return figure;
}

Figure saccade_figure(const Trace& trace, const PlotInputs& inputs) {
  Figure figure;
  figure.file = "plot_saccade.png";
  figure.title = inputs.title + ": saccade profile of the dominant eye";
  const double from_s = inputs.saccade_start_s - 0.05;
  const double to_s = inputs.saccade_end_s + 0.15;
  Series pan{"true pan", kBlack, 1, {}};
  Series speed{"true pan velocity", kRed, 1, {}};
  const auto j = static_cast<std::size_t>(trace.dominant_pan_joint);
  for (std::size_t r = 0; r < trace.rows.size(); ++r) {
    const double t = trace.rows[r].time_s;
    if (t < from_s || t > to_s) continue;
    figure.x.push_back(t);
    const double q = trace.joints_at(r)[j].true_rad;
    pan.y.push_back(q * kDegPerRad);
    double velocity = NAN;
    if (r > 0 && t > trace.rows[r - 1].time_s) {
      velocity = (q - trace.joints_at(r - 1)[j].true_rad) / (t - trace.rows[r - 1].time_s);
    }
    speed.y.push_back(velocity * kDegPerRad);
  }
  figure.panels.push_back({trace.joint_names[j] + " (deg)", {pan}});
  figure.panels.push_back({"velocity (deg/s)", {speed}});
  return figure;
}

Figure reach_figure(const Trace& trace, const PlotInputs& inputs) {
  Figure figure;
  figure.file = "plot_reach.png";
  figure.title = inputs.title + ": the reaching arm's fingertips";
  Series believed{"believed, to target", kBlue, 1, {}};
  Series surface{"true, to surface", kBlack, 1, {}};
  Series speed{"true speed", kRed, 1, {}};
  for (std::size_t r = 0; r < trace.rows.size(); ++r) {
    const TraceRow& row = trace.rows[r];
    if (row.reach_arm < 0) continue;
    figure.x.push_back(row.time_s);
    believed.y.push_back(row.gripper_distance_m);
    surface.y.push_back(row.true_gripper_surface_m);
    double v = NAN;
    if (r > 0 && trace.rows[r - 1].reach_arm == row.reach_arm &&
        row.time_s > trace.rows[r - 1].time_s) {
      const auto& a = trace.rows[r - 1].true_gripper_W_m;
      const auto& b = row.true_gripper_W_m;
      v = std::hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]) /
          (row.time_s - trace.rows[r - 1].time_s);
    }
    speed.y.push_back(v);
  }
  figure.panels.push_back({"distance (m)", {believed, surface}});
  figure.panels.push_back({"speed (m/s)", {speed}});
  return figure;
}

}  // namespace

std::vector<std::string> stage_plots(OutputDirectory& out, const Trace& trace,
                                     const PlotInputs& inputs) {
  std::vector<Figure> figures;
  if (trace.rows.size() >= 2) {
    figures.push_back(gaze_figure(trace, inputs));
    Figure joints = joints_figure(trace, inputs);
    if (!joints.panels.empty()) figures.push_back(std::move(joints));
    if (trace.dominant_pan_joint >= 0 && std::isfinite(inputs.saccade_start_s) &&
        std::isfinite(inputs.saccade_end_s) && inputs.saccade_end_s > inputs.saccade_start_s) {
      Figure saccade = saccade_figure(trace, inputs);
      if (saccade.x.size() >= 2) figures.push_back(std::move(saccade));
    }
    if (trace.reach.accepted) {
      Figure reach = reach_figure(trace, inputs);
      if (reach.x.size() >= 2) figures.push_back(std::move(reach));
    }
  }
  std::vector<std::string> staged;
  for (const Figure& figure : figures) {
    out.stage(figure.file, draw_png(figure));
    staged.push_back(figure.file);
  }
  return staged;
}

}  // namespace cambio::app
