#include "run_plots.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "output_directory.hpp"
#include "plot_figure.hpp"
#include "plot_process.hpp"

namespace cambio::app {

namespace {

using detail::Figure;
using detail::kBlack;
using detail::kBlue;
using detail::kOrange;
using detail::kRed;
using detail::Series;

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

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

/// The joints inputs.joints names, or every joint whose true position moved (at most 6).
std::vector<std::size_t> plotted_joints(const Trace& trace, const PlotInputs& inputs) {
  std::vector<std::size_t> joints;
  if (!inputs.joints.empty()) {
    for (const std::string& name : inputs.joints) {
      const auto it = std::find(trace.joint_names.begin(), trace.joint_names.end(), name);
      if (it == trace.joint_names.end()) {
        throw OutputError("plot_joints.png: no joint '" + name + "' in the trace");
      }
      joints.push_back(static_cast<std::size_t>(it - trace.joint_names.begin()));
    }
    return joints;
  }
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
  return joints;
}

Figure joints_figure(const Trace& trace, const PlotInputs& inputs) {
  const std::vector<std::size_t> joints = plotted_joints(trace, inputs);
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

/// The figures the trace has data for, in stage_plots' order.
std::vector<Figure> figures_of(const Trace& trace, const PlotInputs& inputs) {
  std::vector<Figure> figures;
  if (trace.rows.size() < 2) return figures;
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
  return figures;
}

}  // namespace

StagedPlots stage_plots(OutputDirectory& out, const Trace& trace, const PlotInputs& inputs) {
  StagedPlots plots;
  for (const detail::DrawnFigure& figure : detail::draw_pngs_in_child(figures_of(trace, inputs))) {
    if (figure.png.empty()) {
      // draw_png's own messages start with the file's name.
      plots.missing.push_back(figure.error.starts_with(figure.file + ":")
                                  ? figure.error
                                  : figure.file + ": " + figure.error);
      continue;
    }
    out.stage(figure.file, figure.png);
    plots.staged.push_back(figure.file);
  }
  return plots;
}

}  // namespace cambio::app
