#include "perceive_run.hpp"

#include <cstdio>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "command.hpp"
#include "contact_sheet.hpp"
#include "image_files.hpp"
#include "json_output.hpp"
#include "perceive_result.hpp"

namespace cambio::app {

namespace {

/// Makes `servo` for images of the inputs' size, in place (an SSM is not moved once made). False
/// (the reason printed) when its config is inconsistent or the images are smaller than its finest
/// level.
bool make_servo_or_report(const PerceiveInputs& inputs,
                          std::optional<perception::SensoryServo>& servo) {
  const perception::SsmConfig& config = inputs.config;
  try {
    servo.emplace(config, inputs.left.width_px, inputs.left.height_px);
  } catch (const std::invalid_argument& error) {
    std::cerr << "cambio perceive: inconsistent SSM config: " << error.what() << "\n";
    return false;
  }
  // Where the images are smaller than the finest retina level with the apron its kernels read,
  // every level samples the images' clamped borders, not the scene.
  const int apron = servo->retina(hal::Eye::kLeft).apron();
  const int min_width = config.retina.width_px + 2 * apron;
  const int min_height = config.retina.height_px + 2 * apron;
  if (inputs.left.width_px < min_width || inputs.left.height_px < min_height) {
    std::cerr << "cambio perceive: " << inputs.left_path << " and " << inputs.right_path << " are "
              << inputs.left.width_px << "x" << inputs.left.height_px
              << " px; the SSM needs images of at least " << min_width << "x" << min_height
              << " px (its finest retina level, " << config.retina.width_px << "x"
              << config.retina.height_px << " px, with the " << apron
              << " px its kernels read around it)\n";
    return false;
  }
  return true;
}

void print_summary_line(const perception::DisparityResult& d, const OutputDirectory& out) {
  char disparity_text[32] = "invalid";
  if (d.valid) {
    std::snprintf(disparity_text, sizeof disparity_text, "%.6g",
                  static_cast<double>(d.disparity_px));
  }
  std::printf("disparity %s px, confidence %.2f (level %d); wrote %s and %s\n", disparity_text,
              static_cast<double>(d.confidence), d.level, (out.path() / "result.json").c_str(),
              (out.path() / "contact_sheet.png").c_str());
}

}  // namespace

bool read_perceive_images(PerceiveInputs& inputs) {
  try {
    inputs.left = read_image_file(inputs.left_path, hal::PixelFormat::kGrey8);
    inputs.right = read_image_file(inputs.right_path, hal::PixelFormat::kGrey8);
  } catch (const ImageFileError& error) {
    std::cerr << "cambio perceive: " << error.what() << "\n";
    return false;
  }
  const hal::Image& left = inputs.left;
  const hal::Image& right = inputs.right;
  if (left.width_px != right.width_px || left.height_px != right.height_px) {
    std::cerr << "cambio perceive: the images differ in size: " << inputs.left_path << " is "
              << left.width_px << "x" << left.height_px << ", " << inputs.right_path << " is "
              << right.width_px << "x" << right.height_px << "\n";
    return false;
  }
  return true;
}

int run_perceive(const PerceiveInputs& inputs, OutputDirectory& out) {
  std::optional<perception::SensoryServo> servo;
  if (!make_servo_or_report(inputs, servo)) return kExitBadInput;
  perception::SsmFrame frame = servo->make_frame();
  perception::FeatureRequest request;
  request.motion = false;  // One frame per eye: there is no previous frame to move from.
  if (servo->process(inputs.left, inputs.right, inputs.fixation_left, inputs.fixation_right,
                     request, frame) != hal::Status::kOk) {
    std::cerr << "cambio perceive: the SSM rejected the images\n";
    return kExitFailure;
  }
  out.stage("result.json", json_text(perceive_result_json(inputs, *servo, frame.summary)));
  out.stage("contact_sheet.png", contact_sheet_png(*servo, frame, inputs.left, inputs.right));
  out.commit();
  print_summary_line(frame.summary.disparity, out);
  return kExitOk;
}

}  // namespace cambio::app
