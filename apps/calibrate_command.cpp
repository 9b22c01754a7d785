// `cambio calibrate stereo --images DIR --board 9x6 --square-mm 25 --rig RIG --out DIR`: the
// stereo pair's intrinsics, distortion and relative pose from chessboard views, written as the
// rig's camera_calibration file and ROS camera_info files. The work is in
// calibration/stereo_calibration_run.hpp.
#include <iostream>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

#include "argument_parser.hpp"
#include "cambio/config/shipped_config.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "output_directory.hpp"
#include "stereo_calibration_run.hpp"
#include "stereo_image_pairs.hpp"

namespace cambio::app {

namespace {

constexpr const char* kSubcommands = "stereo";

/// "9x6": inner corners per row x per column. findChessboardCorners needs at least 3 each way
/// (a 2-wide grid has no inner quad to grow from); 50 is beyond any printed board.
ChessboardSpec parse_board(const std::string& text, double square_mm) {
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
    throw UsageError(
        "calibrate stereo: --board expects the board's inner corners as COLUMNSxROWS, each in "
        "[3, 50] (a 10 x 7 squares board is 9x6), found '" +
        text + "'");
  }
  return {columns, rows, square_mm / 1000.0};
}

std::string command_line(std::span<const std::string> args) {
  std::string line = "cambio calibrate stereo";
  for (const auto& arg : args) line += " " + arg;
  return line;
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
  for (const char* required : {"images", "board", "square-mm", "rig", "out"}) {
    if (!parser.has(required)) {
      throw UsageError(std::string("calibrate stereo: --") + required + " is required");
    }
  }
  const double square_mm = parser.number("square-mm", 0.0, config::Range{0.0, 1000.0, true, false},
                                         "a printed board's square, above 0 and at most a metre");
  StereoCalibrationInputs inputs;
  inputs.board = parse_board(parser.value("board"), square_mm);
  inputs.images_dir = parser.value("images");
  inputs.provenance = {command_line(args), parser.value("board") + " inner corners, " +
                                               parser.value("square-mm") + " mm squares"};
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

}  // namespace

int run_calibrate_command(std::span<const std::string> args) {
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::cout << "usage: cambio calibrate stereo --images DIR --board COLSxROWS --square-mm MM "
                 "--rig RIG --out DIR\n"
                 "  stereo  a stereo pair's intrinsics, distortion and relative pose from "
                 "chessboard views (cambio calibrate stereo --help)\n";
    return kExitOk;
  }
  if (args.empty() || args[0] != kSubcommands) {
    throw UsageError("calibrate: " +
                     (args.empty() ? std::string("expected a subcommand")
                                   : "unknown subcommand '" + args[0] + "'") +
                     " (the subcommands are: " + std::string(kSubcommands) + ")");
  }
  return run_stereo(args.subspan(1));
}

}  // namespace cambio::app
