// `cambio calibrate stereo --images DIR --board 9x6 --square-mm 25 --rig RIG --out DIR`: the
// stereo pair's intrinsics, distortion and relative pose from chessboard views, written as the
// rig's camera_calibration file and ROS camera_info files. The work is in
// calibration/stereo_calibration_run.hpp.
// `cambio calibrate hand-eye --views DIR --board 9x6 --square-mm 25 --rig RIG --camera CAM
// --out DIR`: a camera's mount on its link from views of a fixed board at several head poses
// (calibration/hand_eye_calibration_run.hpp).
// `cambio calibrate capture EXPERIMENT.yaml --poses FILE --camera CAM|stereo --out DIR`: moves the
// head through the poses and saves each view with the joints' readings (hand-eye's input), by the
// console's lines (calibration/capture_script.hpp).
#include <filesystem>
#include <initializer_list>
#include <iostream>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

#include "argument_parser.hpp"
#include "cambio/config/shipped_config.hpp"
#include "capture_script.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "console_run.hpp"
#include "hand_eye_calibration_run.hpp"
#include "output_directory.hpp"
#include "stereo_calibration_run.hpp"
#include "stereo_image_pairs.hpp"

namespace cambio::app {

namespace {

constexpr const char* kSubcommands = "stereo, hand-eye, capture";

/// "9x6": inner corners per row x per column. findChessboardCorners needs at least 3 each way
/// (a 2-wide grid has no inner quad to grow from); 50 is beyond any printed board.
ChessboardSpec parse_board(const std::string& text, double square_mm, const std::string& command) {
  const std::size_t x = text.find('x');
  int columns = 0;
  int rows = 0;
  std::size_t used_columns = 0;
  std::size_t used_rows = 0;
  try {
    if (x == std::string::npos) throw std::invalid_argument("no x");
    columns = std::stoi(text.substr(0, x), &used_columns);
    rows = std::stoi(text.substr(x + 1), &used_rows);
  } catch (const std::exception&) {
    used_columns = 0;
  }
  if (used_columns == 0 || used_columns != x || used_rows != text.size() - x - 1 || columns < 3 ||
      rows < 3 || columns > 50 || rows > 50) {
    throw UsageError(command +
                     ": --board expects the board's inner corners as COLUMNSxROWS, each in "
                     "[3, 50] (a 10 x 7 squares board is 9x6), found '" +
                     text + "'");
  }
  return {columns, rows, square_mm / 1000.0};
}

std::string command_line(const std::string& command, std::span<const std::string> args) {
  std::string line = "cambio " + command;
  for (const auto& arg : args) line += " " + arg;
  return line;
}

/// The options every calibrate subcommand needs, present, or a UsageError naming the first not.
void require(const ArgumentParser& parser, std::initializer_list<const char*> options,
             const std::string& command) {
  for (const char* required : options) {
    if (!parser.has(required)) throw UsageError(command + ": --" + required + " is required");
  }
}

/// The board from --board and --square-mm, and its description for the files' provenance.
ChessboardSpec board_option(const ArgumentParser& parser, const std::string& command,
                            std::string& description) {
  const double square_mm = parser.number("square-mm", 0.0, config::Range{0.0, 1000.0, true, false},
                                         "a printed board's square, above 0 and at most a metre");
  description =
      parser.value("board") + " inner corners, " + parser.value("square-mm") + " mm squares";
  return parse_board(parser.value("board"), square_mm, command);
}

int run_stereo(std::span<const std::string> args) {
  ArgumentParser parser("calibrate stereo",
                        "--images DIR --board COLSxROWS --square-mm MM --rig RIG --out DIR");
  parser
      .option("images", "DIR",
              "the views: leftID.* with rightID.* (e.g. left01.png, right01.png), taken with "
              "every joint at zero")
      .option("board", "COLSxROWS", "the chessboard's inner corners, e.g. 9x6")
      .option("square-mm", "MM", "side of one square, in millimetres")
      .option("rig", "RIG", "the rig file (or a shipped rig's name) whose stereo pair this is")
      .option("out", "DIR",
              "where camera_calibration.yaml and the ROS camera_info files go (created)");
  if (!parser.parse(args)) return kExitOk;
  require(parser, {"images", "board", "square-mm", "rig", "out"}, "calibrate stereo");
  StereoCalibrationInputs inputs;
  inputs.board = board_option(parser, "calibrate stereo", inputs.provenance.board);
  inputs.images_dir = parser.value("images");
  inputs.provenance.command_line = command_line("calibrate stereo", args);
  auto rig = load_rig_or_report(config::resolve_config_argument("rigs", parser.value("rig")), {});
  if (!rig) return kExitBadInput;
  inputs.rig = std::move(*rig);
  // Claimed before the work: a run that cannot write its results fails at once.
  OutputDirectory out(parser.value("out"), "calibrate stereo");
  try {
    const StereoCalibrationOutcome outcome = run_stereo_calibration(inputs, out, std::cout);
    return outcome == StereoCalibrationOutcome::kCalibrated ? kExitOk : kExitFailure;
  } catch (const CalibrationInputError& error) {
    std::cerr << "cambio calibrate stereo: " << error.what() << "\n";
    return kExitBadInput;
  }
}

int run_hand_eye(std::span<const std::string> args) {
  ArgumentParser parser("calibrate hand-eye",
                        "--views DIR --board COLSxROWS --square-mm MM --rig RIG --camera CAMERA "
                        "--out DIR");
  parser
      .option("views", "DIR",
              "the views: viewID.* (an image of the fixed board) with viewID.yaml (joints_rad: "
              "the joints' readings when it was taken), at several head poses")
      .option("board", "COLSxROWS", "the chessboard's inner corners, e.g. 9x6")
      .option("square-mm", "MM", "side of one square, in millimetres")
      .option("rig", "RIG", "the rig file (or a shipped rig's name): kinematics and intrinsics")
      .option("camera", "CAMERA", "the camera whose mount on its link is measured")
      .option("out", "DIR", "where camera_calibration.yaml goes (created)");
  if (!parser.parse(args)) return kExitOk;
  require(parser, {"views", "board", "square-mm", "rig", "camera", "out"}, "calibrate hand-eye");
  HandEyeCalibrationInputs inputs;
  inputs.board = board_option(parser, "calibrate hand-eye", inputs.provenance.board);
  inputs.views_dir = parser.value("views");
  inputs.camera = parser.value("camera");
  inputs.provenance.command_line = command_line("calibrate hand-eye", args);
  auto rig = load_rig_or_report(config::resolve_config_argument("rigs", parser.value("rig")), {});
  if (!rig) return kExitBadInput;
  inputs.rig = std::move(*rig);
  OutputDirectory out(parser.value("out"), "calibrate hand-eye");
  try {
    const HandEyeCalibrationOutcome outcome = run_hand_eye_calibration(inputs, out, std::cout);
    return outcome == HandEyeCalibrationOutcome::kCalibrated ? kExitOk : kExitFailure;
  } catch (const CalibrationInputError& error) {
    std::cerr << "cambio calibrate hand-eye: " << error.what() << "\n";
    return kExitBadInput;
  }
}

int run_capture(std::span<const std::string> args) {
  ArgumentParser parser("calibrate capture",
                        "EXPERIMENT.yaml --poses FILE --camera CAMERA|stereo --out DIR "
                        "[--settle-s S]");
  parser.positional("EXPERIMENT.yaml", "the experiment whose rig (and scene, in sim) to drive")
      .option("poses", "FILE", "the head poses: poses: [{neck_pan: 10, neck_tilt: -5, ...}] (deg)")
      .option("camera", "CAMERA|stereo",
              "the stereo camera whose views are saved (viewNN.png, for calibrate hand-eye), or "
              "stereo for both (leftNN.png and rightNN.png, for calibrate stereo)")
      .option("out", "DIR", "where viewNN.png and viewNN.yaml go (a new or empty folder)")
      .option("settle-s", "S", "time at each pose before its view is taken (default 0.5 s)");
  if (!parser.parse(args)) return kExitOk;
  require(parser, {"poses", "camera", "out"}, "calibrate capture");
  const double settle_s = parser.number("settle-s", 0.5, config::Range{0.0, 60.0, true, true},
                                        "seconds at a pose before its view, at most a minute");
  config::ExperimentConfig experiment;
  try {
    experiment = config::load_experiment(*parser.positional_value("EXPERIMENT.yaml"), {});
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }
  // Calibration views are whole frames: a sim camera's foveated rendering (a full-resolution
  // square over a coarse field, a speed-up for the loops) would blur the board's corners outside
  // the square, about 0.4 px, and tilt each view's board pose by a degree or two.
  for (config::CameraConfig& camera : experiment.rig.cameras) {
    camera.sim_foveation = config::SimFoveationConfig{};
  }
  const std::filesystem::path out(parser.value("out"));
  std::error_code error;
  if (std::filesystem::exists(out, error) && !std::filesystem::is_empty(out, error)) {
    std::cerr << "cambio calibrate capture: --out: '" << out.string()
              << "' is not empty; name a new folder (views of one session only)\n";
    return kExitBadInput;
  }
  try {
    const std::vector<CapturePose> poses =
        read_capture_poses(parser.value("poses"), experiment.rig);
    CapturePose start;
    for (const config::JointConfig& joint : experiment.rig.joints) {
      start[joint.name] = joint.initial_position_rad;
    }
    return run_console_script(experiment, capture_script(poses, start, experiment.rig,
                                                         parser.value("camera"), out, settle_s));
  } catch (const CalibrationInputError& input_error) {
    std::cerr << "cambio calibrate capture: " << input_error.what() << "\n";
    return kExitBadInput;
  }
}

}  // namespace

int run_calibrate_command(std::span<const std::string> args) {
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::cout << "usage: cambio calibrate stereo|hand-eye|capture OPTIONS\n"
                 "  stereo    a stereo pair's intrinsics, distortion and relative pose from "
                 "chessboard views (cambio calibrate stereo --help)\n"
                 "  hand-eye  a camera's mount on its link from views of a fixed board at "
                 "several head poses (cambio calibrate hand-eye --help)\n"
                 "  capture   move the head through poses and save each view with the joints' "
                 "readings (cambio calibrate capture --help)\n";
    return kExitOk;
  }
  if (!args.empty() && args[0] == "hand-eye") return run_hand_eye(args.subspan(1));
  if (!args.empty() && args[0] == "capture") return run_capture(args.subspan(1));
  if (args.empty() || args[0] != "stereo") {
    throw UsageError("calibrate: " +
                     (args.empty() ? std::string("expected a subcommand")
                                   : "unknown subcommand '" + args[0] + "'") +
                     " (the subcommands are: " + std::string(kSubcommands) + ")");
  }
  return run_stereo(args.subspan(1));
}

}  // namespace cambio::app
