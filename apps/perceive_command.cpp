// `cambio perceive`: run the Sensory Servo Module once on an image pair and write what it saw:
// result.json (disparity and confidence at the fovea, per-level estimates, moments, timings)
// and contact_sheet.png (the retina levels and feature maps of both eyes, and where each level
// lies in the images). The run is in perception_runs/perceive_run.hpp.
#include <iostream>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "argument_parser.hpp"
#include "cambio/config/config_error.hpp"
#include "cambio/config/map_reader.hpp"
#include "cambio/perception/sensory_servo.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "output_directory.hpp"
#include "perceive_run.hpp"

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

/// --config and --set into `inputs`; false (the issues printed) when the config is invalid.
bool load_config_or_report(const ArgumentParser& parser, PerceiveInputs& inputs) {
  try {
    inputs.config_path =
        parser.has("config") ? parser.value("config") : perception::default_ssm_config_path();
    std::vector<config::ConfigOverride> overrides;
    for (const auto& text : parser.values("set")) overrides.push_back(config::parse_override(text));
    inputs.config = perception::load_ssm_config(inputs.config_path, overrides);
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return false;
  }
  return true;
}

/// The fixation options into `inputs`, the image centre by default (so after the images are
/// read); false (the reason printed) when one lies outside the images.
bool fixations_or_report(const ArgumentParser& parser, PerceiveInputs& inputs) {
  const hal::Image& image = inputs.left;
  perception::PixelPoint fixation_left{image.width_px / 2, image.height_px / 2};
  perception::PixelPoint fixation_right = fixation_left;
  if (parser.has("fixation")) {
    fixation_left = fixation_right = parse_point("fixation", parser.value("fixation"));
  } else if (parser.has("fixation-left")) {
    fixation_left = parse_point("fixation-left", parser.value("fixation-left"));
    fixation_right = parse_point("fixation-right", parser.value("fixation-right"));
  }
  for (const auto& [name, p] :
       {std::pair{"left", fixation_left}, std::pair{"right", fixation_right}}) {
    if (p.x < 0 || p.y < 0 || p.x >= image.width_px || p.y >= image.height_px) {
      std::cerr << "cambio perceive: the " << name << " fixation " << p.x << "," << p.y
                << " is outside the " << image.width_px << "x" << image.height_px << " image\n";
      return false;
    }
  }
  inputs.fixation_left = fixation_left;
  inputs.fixation_right = fixation_right;
  return true;
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
  // Checked and claimed before the work: a run that cannot write its results fails at once.
  OutputDirectory out(parser.value("out"), "perceive");
  if (parser.has("fixation") && (parser.has("fixation-left") || parser.has("fixation-right"))) {
    throw UsageError("perceive: give --fixation or --fixation-left/--fixation-right, not both");
  }
  if (parser.has("fixation-left") != parser.has("fixation-right")) {
    throw UsageError("perceive: --fixation-left and --fixation-right go together");
  }

  PerceiveInputs inputs;
  if (!load_config_or_report(parser, inputs)) return kExitBadInput;
  inputs.left_path = parser.value("left");
  inputs.right_path = parser.value("right");
  if (!read_perceive_images(inputs)) return kExitBadInput;
  if (!fixations_or_report(parser, inputs)) return kExitBadInput;
  return run_perceive(inputs, out);
}

}  // namespace cambio::app
