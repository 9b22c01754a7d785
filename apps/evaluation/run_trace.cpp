#include "run_trace.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "image_files.hpp"
#include "output_directory.hpp"

namespace cambio::app {

namespace {

void append_number(std::string& out, double value) {
  if (std::isnan(value)) {
    out += "nan";
    return;
  }
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

void append_field(std::string& out, double value) {
  out += ',';
  append_number(out, value);
}

void append_field(std::string& out, bool value) {
  out += value ? ",1" : ",0";
}

std::string csv_header(const Trace& trace) {
  std::string out = "time_s";
  for (const auto& joint : trace.joint_names) {
    out += ',' + joint + "_command_rad," + joint + "_believed_rad," + joint + "_true_rad";
  }
  out +=
      ",disparity_px,disparity_confidence,disparity_valid,gaze_action,saccade_active,"
      "target_x_m,target_y_m,target_z_m,dominant_gaze_error_deg,verging_gaze_error_deg,"
      "true_gaze_error_deg,target_occluded,believed_fixation_x_m,believed_fixation_y_m,"
      "believed_fixation_z_m,true_fixation_x_m,true_fixation_y_m,true_fixation_z_m,"
      "fixation_error_m,axis_object,reach_arm,reach_phase,gripper_x_m,gripper_y_m,gripper_z_m,"
      "gripper_distance_m,true_gripper_x_m,true_gripper_y_m,true_gripper_z_m,"
      "true_gripper_surface_m\n";
  return out;
}

/// Row r's line, in csv_header's order.
void append_csv_row(std::string& out, const Trace& trace, std::size_t r) {
  const TraceRow& row = trace.rows[r];
  append_number(out, row.time_s);
  for (const TraceJointSample& joint : trace.joints_at(r)) {
    append_field(out, joint.command_rad);
    append_field(out, joint.believed_rad);
    append_field(out, joint.true_rad);
  }
  append_field(out, row.disparity_valid ? row.disparity_px : kNoValue);
  append_field(out, row.disparity_confidence);
  append_field(out, row.disparity_valid);
  out += ',';
  if (row.gaze_status) out += gaze_action_name(row.action);
  append_field(out, row.saccade_active);
  for (const double v : row.target_W_m) append_field(out, v);
  append_field(out, row.dominant_gaze_error_deg);
  append_field(out, row.verging_gaze_error_deg);
  append_field(out, row.true_gaze_error_deg);
  append_field(out, row.target_occluded);
  for (const double v : row.believed_fixation_W_m) {
    append_field(out, row.believed_fixation_valid ? v : kNoValue);
  }
  for (const double v : row.true_fixation_W_m) {
    append_field(out, row.true_fixation_valid ? v : kNoValue);
  }
  append_field(out, row.fixation_error_m);
  out += ',';
  if (row.axis_object >= 0) out += trace.visit_objects[static_cast<std::size_t>(row.axis_object)];
  out += ',';
  if (row.reach_arm >= 0) {
    out += row.reach_arm == 0 ? "left," : "right,";
    out += reach_phase_name(row.reach_phase);
  } else {
    out += ',';
  }
  for (const double v : row.gripper_W_m) append_field(out, v);
  append_field(out, row.gripper_distance_m);
  for (const double v : row.true_gripper_W_m) append_field(out, v);
  append_field(out, row.true_gripper_surface_m);
  out += '\n';
}

}  // namespace

const char* gaze_action_name(control::GazeAction action) {
  switch (action) {
    case control::GazeAction::kHold:
      return "hold";
    case control::GazeAction::kFixate:
      return "fixate";
    case control::GazeAction::kSaccade:
      return "saccade";
    case control::GazeAction::kPursue:
      return "pursue";
    case control::GazeAction::kMoveJoint:
      return "move_joint";
    case control::GazeAction::kVerge:
      return "verge";  // Never a status's action: a verge command keeps the action going.
  }
  return "unknown";
}

const char* reach_phase_name(control::ReachPhase phase) {
  switch (phase) {
    case control::ReachPhase::kIdle:
      return "idle";
    case control::ReachPhase::kReaching:
      return "reaching";
    case control::ReachPhase::kTouching:
      return "touching";
    case control::ReachPhase::kArrived:
      return "arrived";
    case control::ReachPhase::kRefused:
      return "refused";
  }
  return "unknown";
}

void Trace::add_row(const TraceRow& row, std::span<const TraceJointSample> joint_samples) {
  if (joint_samples.size() != joint_count()) {
    throw std::invalid_argument("trace: a row needs " + std::to_string(joint_count()) +
                                " joint samples, got " + std::to_string(joint_samples.size()));
  }
  rows.push_back(row);
  joints.insert(joints.end(), joint_samples.begin(), joint_samples.end());
}

std::string trace_csv(const Trace& trace) {
  std::string out = csv_header(trace);
  for (std::size_t r = 0; r < trace.rows.size(); ++r) append_csv_row(out, trace, r);
  return out;
}

std::string key_frame_file_name(const KeyFrame& frame) {
  return "key_" + std::to_string(std::llround(frame.time_s * 1000.0)) + "ms_" + frame.camera +
         ".png";
}

void stage_trace(OutputDirectory& out, const Trace& trace) {
  out.stage("trace.csv", trace_csv(trace));
}

}  // namespace cambio::app
