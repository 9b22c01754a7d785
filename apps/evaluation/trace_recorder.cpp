#include "trace_recorder.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "true_gaze.hpp"

namespace cambio::app {

namespace {

int joint_index(const std::vector<std::string>& names, const std::string& name) {
  if (name.empty()) return -1;
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    throw std::invalid_argument("trace: pan joint '" + name + "' is not one of the rig's joints");
  }
  return static_cast<int>(it - names.begin());
}

void check_sources(const TraceSources& sources, double rate_hz, double duration_s) {
  if (sources.targets == nullptr) throw std::invalid_argument("trace: no targets channel");
  if (sources.truth == nullptr) throw std::invalid_argument("trace: no ground truth");
  if (sources.dominant_camera.empty() || sources.verging_camera.empty()) {
    throw std::invalid_argument("trace: both eyes' cameras must be named");
  }
  if (!(rate_hz > 0.0) || !(duration_s > 0.0) || !std::isfinite(rate_hz * duration_s)) {
    throw std::invalid_argument("trace: the rate and duration must be positive");
  }
  const int joints = static_cast<int>(sources.joint_names.size());
  for (const auto& source : sources.believed) {
    if (source.channel == nullptr) throw std::invalid_argument("trace: a null believed channel");
    for (const int index : source.rig_indices) {
      if (index < 0 || index >= joints) {
        throw std::invalid_argument("trace: believed joint index " + std::to_string(index) +
                                    " is outside the rig's " + std::to_string(joints) + " joints");
      }
    }
  }
}

}  // namespace

TraceRecorder::TraceRecorder(TraceSources sources, double rate_hz, double duration_s)
    : sources_(std::move(sources)) {
  check_sources(sources_, rate_hz, duration_s);
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
  TraceRow row;
  row.time_s = time_s;
  read_joints();
  read_gaze(row);
  const Eigen::Vector3d target_W = dominant_target_W(row);
  row.target_W_m = detail::to_array(target_W);
  const detail::TrueEyes eyes = detail::true_eyes(sources_);
  const sim::RayHit hit = detail::record_true_gaze(row, eyes, target_W, sources_);
  detail::record_fixation(row, status_, eyes);
  if (sources_.arms != nullptr) {
    sources_.arms->read(arm_status_);
    if (sources_.arms->version() > 0) record_arms(row, hit);
  }
  trace_.add_row(row, scratch_);
  return hal::Status::kOk;
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
        sources_.truth->render_as_seen(*camera, frame.image);
        trace_.key_frames.push_back(std::move(frame));
      } catch (const std::exception& error) {
        trace_.problems.push_back("key frame of '" + *camera + "' at " + std::to_string(time_s) +
                                  " s: " + error.what());
      }
    }
  }
}

void TraceRecorder::read_joints() {
  // A torn read keeps the previous frame (SeqlockChannel::read leaves it untouched).
  sources_.targets->read(targets_);
  const std::size_t joints = trace_.joint_count();
  for (std::size_t i = 0; i < joints; ++i) {
    TraceJointSample& sample = scratch_[i];
    sample = {};
    if (static_cast<int>(i) < targets_.count &&
        targets_.commands[i].mode == hal::CommandMode::kPosition) {
      sample.command_rad = targets_.commands[i].value;
    }
    sample.true_rad = sources_.truth->joint_position_rad(sources_.joint_names[i]);
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
}

void TraceRecorder::read_gaze(TraceRow& row) {
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
}

Eigen::Vector3d TraceRecorder::dominant_target_W(const TraceRow& row) {
  sim::GroundTruth& truth = *sources_.truth;
  const bool pursuing = row.gaze_status && row.action == control::GazeAction::kPursue;
  if (!pursuing) pursuit_anchored_ = false;
  const bool named = !sources_.target_object.empty();
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
    return X_WO * pursuit_anchor_O_;
  }
  if (named && !row.gaze_status) return truth.X_WO(sources_.target_object).translation();
  if (row.gaze_status && status_.target_set) return detail::to_vector(status_.target_W_m);
  return Eigen::Vector3d::Constant(kNoValue);
}

}  // namespace cambio::app
