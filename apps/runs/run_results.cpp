#include "run_results.hpp"

#include <iostream>

#include "image_files.hpp"
#include "run_plots.hpp"
#include "run_summary.hpp"
#include "stop_signal.hpp"

namespace cambio::app {

namespace {

/// An image illustrates the results: one that cannot be encoded (memory short at the end of a
/// run) is a warning, and the results stand. A failed write stays an error, as for every file.
void stage_image(OutputDirectory& out, const std::string& name, const hal::Image& image) {
  std::vector<std::uint8_t> png;
  try {
    png = encode_png(image);
  } catch (const std::exception& error) {
    std::cerr << "cambio run: warning: image not written: " << name << ": " << error.what() << "\n";
    return;
  }
  out.stage(name, png);
}

/// The key frames and each camera's last frame; cameras that never delivered a frame have none.
void stage_images(OutputDirectory& out, MainJob& job) {
  if (const Trace* trace = job.trace()) {
    for (const KeyFrame& frame : trace->key_frames) {
      stage_image(out, key_frame_file_name(frame), frame.image);
    }
  }
  const auto frames = job.last_frames();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].sequence == 0) continue;
    stage_image(out, job.cameras()[i].name + ".png", frames[i]);
  }
}

/// The plots' inputs; the saccade window from the last saccade command to the dominant eye's
/// stop, when the metrics found one.
PlotInputs plot_inputs(const config::ExperimentConfig& experiment, const MainJob& job,
                       const MainJobResult& result,
                       const std::optional<RunEvaluation>& evaluation) {
  PlotInputs plots;
  plots.title = experiment.name;
  plots.joints = job.head_joint_names();
  if (evaluation) {
    const auto saccade = evaluation->metrics.find("saccade_duration_s");
    const auto start = last_command_time(experiment, result, config::GazeAction::kSaccade);
    if (saccade && start) {
      plots.saccade_start_s = *start;
      plots.saccade_end_s = *start + *saccade;
    }
  }
  return plots;
}

}  // namespace

void write_run_results(OutputDirectory& out, const config::ExperimentConfig& experiment,
                       MainJob& job, const MainJobResult& result, const RunOutcome& outcome,
                       const std::optional<RunEvaluation>& evaluation) {
  // The results first (the trace, the summary), then what illustrates them (images, plots), which
  // may fail without taking the results with them.
  if (const Trace* trace = job.trace()) stage_trace(out, *trace);
  out.stage("summary.json",
            json_text(summary_json(experiment, result, outcome, job.trace(), evaluation)));
  stage_images(out, job);
  if (const Trace* trace = job.trace()) {
    const PlotInputs plots = plot_inputs(experiment, job, result, evaluation);
    if (stop_hurried()) {
      std::cerr << "cambio run: plots skipped: a second signal asked to hurry\n";
    } else {
      // Plots are optional: one that cannot be made is a warning, and the results stand.
      for (const std::string& missing : stage_plots(out, *trace, plots).missing) {
        std::cerr << "cambio run: warning: plot not made: " << missing << "\n";
      }
    }
  }
  out.commit();
  std::cerr << "cambio run: wrote " << out.path().string() << " (" << out.files().size()
            << " files)\n";
}

}  // namespace cambio::app
