#pragma once

// `cambio perceive`'s run: the Sensory Servo Module once on an image pair, and what it saw
// written to an output directory: result.json (disparity and confidence at the fovea, per-level
// estimates, moments, timings) and contact_sheet.png (the retina levels and feature maps of both
// eyes, and where each level lies in the images).

#include <string>

#include "cambio/hal/image.hpp"
#include "cambio/perception/sensory_servo.hpp"
#include "output_directory.hpp"

namespace cambio::app {

struct PerceiveInputs {
  std::string left_path;  ///< As given: named in messages and result.json.
  std::string right_path;
  hal::Image left;  ///< grey8, the size of `right`.
  hal::Image right;
  perception::PixelPoint fixation_left;  ///< Inside the images.
  perception::PixelPoint fixation_right;
  perception::SsmConfig config;
  std::string config_path;  ///< Where `config` came from; empty for the built-in defaults.
};

/// Reads `inputs.left_path` and `inputs.right_path` into `inputs.left` and `inputs.right` as
/// grey8. False (the reason printed) when a file cannot be read or the two differ in size.
/// Silences OpenCV's own warnings for the rest of the process.
bool read_perceive_images(PerceiveInputs& inputs);

/// Runs the SSM once on the pair and writes result.json and contact_sheet.png into `out`,
/// committed as a set, then prints one line. Returns the exit status: kExitBadInput (the reason
/// printed) for a config the SSM cannot run on images of this size, kExitFailure when the SSM
/// rejects the images. Throws OutputError when the files cannot be written.
int run_perceive(const PerceiveInputs& inputs, OutputDirectory& out);

}  // namespace cambio::app
