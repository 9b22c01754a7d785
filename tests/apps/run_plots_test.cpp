// The experiment plots: PLplot writes them, they decode as PNG, and they show something.

#include "run_plots.hpp"

#include <cmath>
#include <filesystem>
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
    const auto staged = stage_plots(out, trace, inputs);
    EXPECT_EQ(staged,
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
    EXPECT_EQ(stage_plots(out, trace, inputs),
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
  EXPECT_TRUE(stage_plots(out, Trace{}, PlotInputs{}).empty());
}

}  // namespace
}  // namespace cambio::app
