#pragma once

// An experiment's plots as PNG, drawn with PLplot (pngcairo device) from its recorded Trace.

#include <limits>
#include <string>
#include <vector>

#include "run_trace.hpp"

namespace cambio::app {

class OutputDirectory;

struct PlotInputs {
  std::string title;  ///< Shown on every plot (the experiment's name).
  /// The joints plot_joints.png draws (names in the trace), e.g. the head's; empty: every joint
  /// whose true position moved during the run (at most 6).
  std::vector<std::string> joints;
  /// The saccade to draw in plot_saccade.png (s since the start): from its command to the
  /// dominant eye's stop (the command time plus RunMetrics' saccade_duration_s). NaN: none.
  double saccade_start_s = std::numeric_limits<double>::quiet_NaN();
  double saccade_end_s = std::numeric_limits<double>::quiet_NaN();
};

/// Draws and stages in `out`:
///  - plot_gaze.png: measured disparity (px) and the eyes' true gaze errors (deg) over time;
///  - plot_joints.png: the joints' command, believed and true angles (deg) over time;
///  - plot_saccade.png (with a saccade window and the dominant pan joint): the dominant eye's
///    true pan (deg) and its speed (deg/s) around the saccade;
///  - plot_reach.png (when the run made a reach): the reaching arm's fingertips, their believed
///    distance to the target and their true distance to the target object's surface (m), and
///    their true speed (m/s), from the reach command on.
/// The plots are optional results: they are drawn in a child process (plot_process.hpp), and one
/// that cannot be drawn (PLplot's message, or the signal that ended the plotting) is listed in
/// `missing`, never an error of the run. Throws OutputError only for inputs that name no data
/// (a joint the trace does not have). Call after the run, from one thread. Not real-time safe.
struct StagedPlots {
  std::vector<std::string> staged;   ///< File names, in the order above.
  std::vector<std::string> missing;  ///< "plot_x.png: why", one per plot not made.
};
StagedPlots stage_plots(OutputDirectory& out, const Trace& trace, const PlotInputs& inputs);

}  // namespace cambio::app
