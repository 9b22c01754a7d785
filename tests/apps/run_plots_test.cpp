// The experiment plots: PLplot writes them, they decode as PNG, and they show something.

#include "run_plots.hpp"

#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "output_directory.hpp"

namespace cambio::app {
namespace {

/// 2 s at 200 Hz: a saccade of the dominant pan (0 to 0.5 rad, a smooth step over 1.0..1.3 s),
/// disparity decaying after it, gaze errors, and a still joint the default selection skips.
Trace synthetic_trace() {
  Trace trace;
  trace.joint_names = {"neck_pan", "left_eye_pan", "right_eye_pan"};
  trace.dominant_pan_joint = 1;
  trace.verging_pan_joint = 2;
  for (int k = 0; k <= 400; ++k) {
    const double t = k * 0.005;
    const double s = std::clamp((t - 1.0) / 0.3, 0.0, 1.0);
    const double pan = 0.5 * (s - std::sin(2 * std::numbers::pi * s) / (2 * std::numbers::pi));
    TraceRow row;
    row.time_s = t;
    row.disparity_valid = t < 1.0 || t > 1.3;
    row.disparity_px = t > 1.3 ? 6.0 * std::exp(-(t - 1.3) / 0.05) : 0.2;
    row.dominant_gaze_error_deg = 0.05 + (t > 1.0 && t < 1.3 ? 10.0 * (1 - s) : 0.0);
    row.verging_gaze_error_deg = t > 1.0 && t < 1.5 ? 2.0 : 0.1;
    row.target_occluded = t > 1.7 && t < 1.8;
    const std::vector<TraceJointSample> joints = {
        {0.0, 0.0, 0.0}, {pan, pan + 0.001, pan}, {pan + 0.1, pan + 0.1, pan + 0.1}};
    trace.add_row(row, joints);
  }
  return trace;
}

class RunPlotsTest : public ::testing::Test {
 protected:
  RunPlotsTest()
      : directory_(std::filesystem::temp_directory_path() /
                   ("cambio_run_plots_test_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(directory_);
  }
  ~RunPlotsTest() override { std::filesystem::remove_all(directory_); }

  std::filesystem::path directory_;
};

/// Decodes a staged PNG and checks it holds a drawing: its size, and ink of several kinds
/// (not one flat colour).
void expect_drawn(const std::filesystem::path& path) {
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty()) << path;
  EXPECT_EQ(image.cols, 1200) << path;
  EXPECT_GT(image.rows, 300) << path;
  cv::Scalar mean, stddev;
  cv::meanStdDev(image, mean, stddev);
  EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 10.0) << path << " looks uniform";
  // Mostly white background with dark axes and coloured curves.
  int white = 0, dark = 0, red = 0;
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);  // BGR
      if (p[0] > 240 && p[1] > 240 && p[2] > 240) ++white;
      if (p[0] < 60 && p[1] < 60 && p[2] < 60) ++dark;
      if (p[2] > 150 && p[1] < 90 && p[0] < 90) ++red;
    }
  }
  EXPECT_GT(white, image.rows * image.cols / 2) << path;
  EXPECT_GT(dark, 1000) << path;
  EXPECT_GT(red, 200) << path;
}

TEST_F(RunPlotsTest, WritesTheGazeJointAndSaccadePlots) {
  const Trace trace = synthetic_trace();
  PlotInputs inputs;
  inputs.title = "saccade";
  inputs.saccade_start_s = 1.0;
  inputs.saccade_end_s = 1.3;
  {
    OutputDirectory out(directory_, "test");
    const auto plots = stage_plots(out, trace, inputs);
    EXPECT_TRUE(plots.missing.empty());
    EXPECT_EQ(plots.staged,
              (std::vector<std::string>{"plot_gaze.png", "plot_joints.png", "plot_saccade.png"}));
    out.commit();
  }
  for (const char* name : {"plot_gaze.png", "plot_joints.png", "plot_saccade.png"}) {
    expect_drawn(directory_ / name);
  }
  // The joints plot draws the two eyes that moved (two panels), not the still neck.
  const cv::Mat joints = cv::imread((directory_ / "plot_joints.png").string());
  EXPECT_EQ(joints.rows, 2 * 330 + 60);
}

TEST_F(RunPlotsTest, DrawsAgainAfterAPlotAndSkipsTheSaccadeWithoutOne) {
  // PLplot's global state is reset between plots: a second set draws as well.
  const Trace trace = synthetic_trace();
  PlotInputs inputs;
  inputs.joints = {"neck_pan", "left_eye_pan", "right_eye_pan"};
  for (int round = 0; round < 2; ++round) {
    OutputDirectory out(directory_, "test");
    EXPECT_EQ(stage_plots(out, trace, inputs).staged,
              (std::vector<std::string>{"plot_gaze.png", "plot_joints.png"}));
    out.commit();
  }
  expect_drawn(directory_ / "plot_gaze.png");
  EXPECT_EQ(cv::imread((directory_ / "plot_joints.png").string()).rows, 3 * 330 + 60);
}

TEST_F(RunPlotsTest, AnUnknownJointIsAnOutputErrorNotACrash) {
  PlotInputs inputs;
  inputs.joints = {"no_such_joint"};
  OutputDirectory out(directory_, "test");
  EXPECT_THROW(stage_plots(out, synthetic_trace(), inputs), OutputError);
  // An empty trace has nothing to plot.
  EXPECT_TRUE(stage_plots(out, Trace{}, PlotInputs{}).staged.empty());
}

/// Stages the synthetic trace's plots with this process's address space limited to what it maps
/// now plus a little: too little for fonts, cairo's surfaces and GLib's thread stacks. Exits 0
/// when both plots are missing with a reason and this process lived to say so.
[[noreturn]] void plot_under_a_tight_limit(const std::filesystem::path& directory,
                                           const Trace& trace) {
  OutputDirectory out(directory, "test");
  std::ifstream status("/proc/self/status");
  std::string line;
  long vm_size_kib = 0;
  while (std::getline(status, line)) {
    if (line.rfind("VmSize:", 0) == 0) vm_size_kib = std::stol(line.substr(7));
  }
  const auto limit = static_cast<rlim_t>(vm_size_kib + 4 * 1024) * 1024;
  const rlimit as{limit, limit};
  if (setrlimit(RLIMIT_AS, &as) != 0) std::_Exit(3);
  const StagedPlots plots = stage_plots(out, trace, PlotInputs{});
  if (!plots.staged.empty() || plots.missing.size() != 2) std::_Exit(4);
  for (const auto& missing : plots.missing) {
    std::fprintf(stderr, "missing: %s\n", missing.c_str());
    if (missing.rfind("plot_", 0) != 0) std::_Exit(5);
  }
  std::_Exit(0);
}

// Under an address-space limit the plotting stack ends the process (GLib-ERROR creating a
// thread: SIGTRAP), which lost a finished run's every result. Drawn in a child, the plots are
// missing with the reason and the caller carries on. The limit is set in a forked copy of this
// test (a death test) so the other tests keep theirs.
TEST_F(RunPlotsTest, APlottingStackThatDiesCostsThePlotsNotTheCaller) {
  const Trace trace = synthetic_trace();
  EXPECT_EXIT(plot_under_a_tight_limit(directory_, trace), ::testing::ExitedWithCode(0),
              "missing: plot_gaze.png: ");
}

}  // namespace
}  // namespace cambio::app
