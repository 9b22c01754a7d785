#include "run_trace.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <system_error>
#include <utility>

#include <Eigen/Geometry>

#include "image_files.hpp"
#include "output_directory.hpp"

namespace cambio::app {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

/// atan2(|a x b|, a . b): accurate at the small angles scored here, where acos loses half the
/// digits.
double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * kDegPerRad;
}

std::array<double, 3> to_array(const Eigen::Vector3d& p) {
  return {p.x(), p.y(), p.z()};
}

Eigen::Vector3d to_vector(const std::array<double, 3>& p) {
  return {p[0], p[1], p[2]};
}

/// The midpoint of the shortest segment between the lines o1 + s d1 and o2 + t d2 (unit d),
/// when they converge in front of both origins (s, t > 0); false for parallel or diverging
/// axes.
bool closest_point(const Eigen::Vector3d& o1, const Eigen::Vector3d& d1, const Eigen::Vector3d& o2,
                   const Eigen::Vector3d& d2, Eigen::Vector3d& midpoint) {
  const Eigen::Vector3d w0 = o1 - o2;
  const double b = d1.dot(d2);
  const double d = d1.dot(w0);
  const double e = d2.dot(w0);
  const double denominator = 1.0 - b * b;
  if (denominator < 1e-12) return false;
  const double s = (b * e - d) / denominator;
  const double t = (e - b * d) / denominator;
  if (!(s > 0.0 && t > 0.0)) return false;
  midpoint = 0.5 * ((o1 + s * d1) + (o2 + t * d2));
  return true;
}

int joint_index(const std::vector<std::string>& names, const std::string& name) {
  if (name.empty()) return -1;
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    throw std::invalid_argument("trace: pan joint '" + name + "' is not one of the rig's joints");
  }
  return static_cast<int>(it - names.begin());
}

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

TraceRecorder::TraceRecorder(TraceSources sources, double rate_hz, double duration_s)
    : sources_(std::move(sources)) {
  if (sources_.targets == nullptr) throw std::invalid_argument("trace: no targets channel");
  if (sources_.truth == nullptr) throw std::invalid_argument("trace: no ground truth");
  if (sources_.dominant_camera.empty() || sources_.verging_camera.empty()) {
    throw std::invalid_argument("trace: both eyes' cameras must be named");
  }
  if (!(rate_hz > 0.0) || !(duration_s > 0.0) || !std::isfinite(rate_hz * duration_s)) {
    throw std::invalid_argument("trace: the rate and duration must be positive");
  }
  const int joints = static_cast<int>(sources_.joint_names.size());
  for (const auto& source : sources_.believed) {
    if (source.channel == nullptr) throw std::invalid_argument("trace: a null believed channel");
    for (const int index : source.rig_indices) {
      if (index < 0 || index >= joints) {
        throw std::invalid_argument("trace: believed joint index " + std::to_string(index) +
                                    " is outside the rig's " + std::to_string(joints) + " joints");
      }
    }
  }
  trace_.joint_names = sources_.joint_names;
  trace_.dominant_pan_joint = joint_index(sources_.joint_names, sources_.dominant_pan_joint);
  trace_.verging_pan_joint = joint_index(sources_.joint_names, sources_.verging_pan_joint);
  // The rows needed, plus one for the sample at the end time itself.
  const double rows = std::ceil(rate_hz * duration_s) + 1.0;
  capacity_rows_ =
      rows >= static_cast<double>(kMaxTraceRows) ? kMaxTraceRows : static_cast<std::size_t>(rows);
  trace_.visit_objects = sources_.visit_objects;
  key_frame_done_.assign(sources_.key_frame_times_s.size(), false);
  believed_frames_.resize(sources_.believed.size());
}

void TraceRecorder::configure() {
  sim::GroundTruth& truth = *sources_.truth;
  truth.X_WC(sources_.dominant_camera);
  truth.X_WC(sources_.verging_camera);
  for (const auto& joint : sources_.joint_names) truth.joint_position_rad(joint);
  if (!sources_.target_object.empty()) truth.X_WO(sources_.target_object);
  for (const std::string& object : sources_.visit_objects) truth.X_WO(object);
  for (const auto& chain : sources_.arm_chains) {
    if (!chain) continue;
    truth.X_WL(chain->names[3]);
    truth.joint_position_rad(chain->names[4]);
  }
  trace_.rows.reserve(capacity_rows_);
  trace_.joints.reserve(capacity_rows_ * trace_.joint_count());
  scratch_.resize(trace_.joint_count());
}

hal::Status TraceRecorder::update(const hal::LoopTick& tick) noexcept {
  return guarded([&] { return record(tick); });
}

void TraceRecorder::render_key_frames(double time_s) {
  for (std::size_t i = 0; i < key_frame_done_.size(); ++i) {
    if (key_frame_done_[i] || time_s < sources_.key_frame_times_s[i]) continue;
    key_frame_done_[i] = true;
    for (const std::string* camera : {&sources_.dominant_camera, &sources_.verging_camera}) {
      KeyFrame frame;
      frame.time_s = time_s;
      frame.camera = *camera;
      try {
        sources_.truth->render(*camera, 0, 0, sim::ViewOptions{}, frame.image, nullptr);
        trace_.key_frames.push_back(std::move(frame));
      } catch (const std::exception& error) {
        trace_.problems.push_back("key frame of '" + *camera + "' at " + std::to_string(time_s) +
                                  " s: " + error.what());
      }
    }
  }
}

hal::Status TraceRecorder::record(const hal::LoopTick& tick) {
  if (!started_) {
    started_ = true;
    start_ns_ = tick.deadline_ns;
  }
  const double time_s = static_cast<double>(tick.deadline_ns - start_ns_) * 1e-9;
  render_key_frames(time_s);
  if (trace_.rows.size() >= capacity_rows_) {
    trace_.truncated = true;
    return hal::Status::kOk;
  }
  sim::GroundTruth& truth = *sources_.truth;
  TraceRow row;
  row.time_s = time_s;

  // Joints. A torn read keeps the previous frame (SeqlockChannel::read leaves it untouched).
  sources_.targets->read(targets_);
  const std::size_t joints = trace_.joint_count();
  for (std::size_t i = 0; i < joints; ++i) {
    TraceJointSample& sample = scratch_[i];
    sample = {};
    if (static_cast<int>(i) < targets_.count &&
        targets_.commands[i].mode == hal::CommandMode::kPosition) {
      sample.command_rad = targets_.commands[i].value;
    }
    sample.true_rad = truth.joint_position_rad(sources_.joint_names[i]);
  }
  for (std::size_t s = 0; s < sources_.believed.size(); ++s) {
    const BelievedStateSource& source = sources_.believed[s];
    control::JointStateFrame& frame = believed_frames_[s];
    source.channel->read(frame);
    if (source.channel->version() == 0) continue;
    const std::size_t n =
        std::min(static_cast<std::size_t>(frame.count), source.rig_indices.size());
    for (std::size_t k = 0; k < n; ++k) {
      scratch_[static_cast<std::size_t>(source.rig_indices[k])].believed_rad =
          frame.states[k].position_rad;
    }
  }

  // What the gaze loop says and what the SSM measured.
  if (sources_.gaze != nullptr) {
    sources_.gaze->read(status_);
    row.gaze_status = sources_.gaze->version() > 0;
  }
  if (row.gaze_status) {
    row.action = status_.action;
    row.saccade_active = status_.saccade_active;
  }
  if (sources_.ssm != nullptr) {
    sources_.ssm->read(summary_);
    if (summary_.sequence > 0) {
      row.disparity_valid = summary_.disparity.valid;
      row.disparity_px = summary_.disparity.disparity_px;
      row.disparity_confidence = summary_.disparity.confidence;
    }
  } else if (row.gaze_status) {
    row.disparity_valid = status_.disparity_valid;
    row.disparity_px = status_.disparity_px;
    row.disparity_confidence = status_.disparity_confidence;
  }

  // The dominant eye's target point.
  if (!(row.gaze_status && row.action == control::GazeAction::kPursue)) pursuit_anchored_ = false;
  const bool named = !sources_.target_object.empty();
  Eigen::Vector3d target_W = Eigen::Vector3d::Constant(kNoValue);
  const bool pursuing = row.gaze_status && row.action == control::GazeAction::kPursue;
  if (named && pursuing) {
    // Pursuit follows what the dominant eye fixated when it began: that point of the object,
    // carried with it (a sphere's front point and its centre drift apart as it crosses the field).
    const Eigen::Isometry3d X_WO = truth.X_WO(sources_.target_object);
    if (!pursuit_anchored_) {
      const Eigen::Isometry3d X_WD = truth.X_WC(sources_.dominant_camera);
      const sim::RayHit start = truth.cast_ray(X_WD.translation(), X_WD.linear().col(2));
      pursuit_anchor_O_ = start.hit && start.object == sources_.target_object
                              ? Eigen::Vector3d(X_WO.inverse() * start.p_W)
                              : Eigen::Vector3d::Zero();
      pursuit_anchored_ = true;
    }
    target_W = X_WO * pursuit_anchor_O_;
  } else if (named && !row.gaze_status) {
    target_W = truth.X_WO(sources_.target_object).translation();
  } else if (row.gaze_status && status_.target_set) {
    target_W = to_vector(status_.target_W_m);
  }
  row.target_W_m = to_array(target_W);

  // True gaze errors and occlusion.
  const Eigen::Isometry3d X_WD = truth.X_WC(sources_.dominant_camera);
  const Eigen::Isometry3d X_WV = truth.X_WC(sources_.verging_camera);
  const Eigen::Vector3d o_d = X_WD.translation(), axis_d = X_WD.linear().col(2);
  const Eigen::Vector3d o_v = X_WV.translation(), axis_v = X_WV.linear().col(2);
  const bool have_target = target_W.allFinite();
  if (have_target) row.dominant_gaze_error_deg = angle_deg(axis_d, target_W - o_d);
  const sim::RayHit hit = truth.cast_ray(o_d, axis_d);
  Eigen::Vector3d verging_target_W = Eigen::Vector3d::Constant(kNoValue);
  if (hit.hit) {
    verging_target_W = hit.p_W;
  } else if (have_target) {
    verging_target_W = o_d + std::max(0.0, (target_W - o_d).dot(axis_d)) * axis_d;
  }
  if (verging_target_W.allFinite()) {
    row.verging_gaze_error_deg = angle_deg(axis_v, verging_target_W - o_v);
    const Eigen::Vector3d p_V = X_WV.inverse() * verging_target_W;
    if (p_V.z() > 0.0 && sources_.verging_focal_px > 0.0) {
      // The point is at the dominant image's centre: the disparity is the verging image's x.
      const double x_px = sources_.verging_focal_px * p_V.x() / p_V.z();
      row.true_disparity_px = sources_.verging_eye_is_right ? -x_px : x_px;
    }
    row.target_occluded =
        truth.segment_blocker(o_v, verging_target_W, hit.hit ? hit.object : std::string()).hit;
  }
  if (named && hit.hit && hit.object != sources_.target_object) row.target_occluded = true;
  if (hit.hit) {
    const auto& objects = sources_.visit_objects;
    const auto it = std::find(objects.begin(), objects.end(), hit.object);
    if (it != objects.end()) row.axis_object = static_cast<int>(it - objects.begin());
  }
  row.true_gaze_error_deg = std::fmax(row.dominant_gaze_error_deg, row.verging_gaze_error_deg);

  // Believed against true fixation.
  if (row.gaze_status && status_.believed_fixation_valid) {
    row.believed_fixation_valid = true;
    row.believed_fixation_W_m = status_.believed_fixation_W_m;
  }
  Eigen::Vector3d fixation_W = Eigen::Vector3d::Zero();
  if (closest_point(o_d, axis_d, o_v, axis_v, fixation_W)) {
    row.true_fixation_valid = true;
    row.true_fixation_W_m = to_array(fixation_W);
  }
  if (row.believed_fixation_valid && row.true_fixation_valid) {
    row.fixation_error_m = (to_vector(row.believed_fixation_W_m) - fixation_W).norm();
  }
  if (sources_.arms != nullptr) {
    sources_.arms->read(arm_status_);
    if (sources_.arms->version() > 0) record_arms(row, hit);
  }
  trace_.add_row(row, scratch_);
  return hal::Status::kOk;
}

void TraceRecorder::record_arms(TraceRow& row, const sim::RayHit& dominant_hit) {
  sim::GroundTruth& truth = *sources_.truth;
  ReachRecord& reach = trace_.reach;
  int side = -1;
  std::int64_t newest_ns = 0;
  for (int s = 0; s < 2; ++s) {
    const control::ArmStatus::Arm& arm = arm_status_.arms[static_cast<std::size_t>(s)];
    if (arm.phase == control::ReachPhase::kRefused && !arm_status_.refusal().empty()) {
      reach.refused = true;
      reach.refusal = std::string(arm_status_.refusal());
    }
    if (sources_.arm_chains[static_cast<std::size_t>(s)] && arm.command_ns > newest_ns) {
      side = s;
      newest_ns = arm.command_ns;
    }
  }
  if (side < 0) return;
  const control::ArmStatus::Arm& arm = arm_status_.arms[static_cast<std::size_t>(side)];
  const control::ArmChain& chain = *sources_.arm_chains[static_cast<std::size_t>(side)];
  row.reach_arm = side;
  row.reach_phase = arm.phase;
  row.gripper_W_m = arm.gripper_W_m;
  row.gripper_distance_m = arm.distance_to_target_m;
  const double opening_rad = truth.joint_position_rad(chain.names[4]);
  const Eigen::Vector3d tip_W =
      truth.X_WL(chain.names[3]) * Eigen::Vector3d(chain.hand_m(opening_rad), 0, 0);
  row.true_gripper_W_m = to_array(tip_W);
  const bool named = !sources_.target_object.empty();
  if (named) row.true_gripper_surface_m = truth.distance_to_object_m(sources_.target_object, tip_W);
  if (arm.command_ns != last_reach_command_ns_) {
    // A new reach: the stereo estimate it took against where the dominant eye truly looked.
    last_reach_command_ns_ = arm.command_ns;
    const bool refused = reach.refused;
    const std::string refusal = reach.refusal;
    reach = ReachRecord{};
    reach.refused = refused;
    reach.refusal = refusal;
    reach.accepted = true;
    reach.arm = side;
    reach.command_s = static_cast<double>(arm.command_ns - start_ns_) * 1e-9;
    reach.estimate_W_m = arm.target_W_m;
    if (dominant_hit.hit && (!named || dominant_hit.object == sources_.target_object)) {
      reach.true_target_W_m = to_array(dominant_hit.p_W);
      reach.estimated_target_error_m = (to_vector(arm.target_W_m) - dominant_hit.p_W).norm();
    }
  }
  if (arm.touch_ns != 0 && std::isnan(reach.touch_s)) {
    reach.touch_s = static_cast<double>(arm.touch_ns - start_ns_) * 1e-9;
    if (named) {
      reach.touch_position_error_m =
          std::abs(truth.end_effector_gap_m(chain.names[4], sources_.target_object));
    }
  }
  reach.final_phase = arm.phase;
}

std::string trace_csv(const Trace& trace) {
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
  for (std::size_t r = 0; r < trace.rows.size(); ++r) {
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
  return out;
}

std::string key_frame_file_name(const KeyFrame& frame) {
  return "key_" + std::to_string(std::llround(frame.time_s * 1000.0)) + "ms_" + frame.camera +
         ".png";
}

void stage_trace(OutputDirectory& out, const Trace& trace) {
  out.stage("trace.csv", trace_csv(trace));
  for (const KeyFrame& frame : trace.key_frames) {
    out.stage(key_frame_file_name(frame), encode_png(frame.image));
  }
}

}  // namespace cambio::app
