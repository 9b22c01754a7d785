#pragma once

// What an experiment run did over time, for scoring (run_metrics.hpp), trace.csv, plots
// (run_plots.hpp) and key frames: the TraceRecorder samples the control side's channels and the
// simulator's ground truth at the control rate.

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cambio/control/arm_chain.hpp"
#include "cambio/control/arm_command.hpp"
#include "cambio/control/gaze_command.hpp"
#include "cambio/control/joint_frames.hpp"
#include "cambio/hal/image.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/perception/sensory_servo.hpp"
#include "cambio/sim/ground_truth.hpp"

namespace cambio::app {

class OutputDirectory;

inline constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

/// One joint at one sample (rad). command_rad is NaN while the joint is commanded in velocity
/// mode or no target frame has arrived; believed_rad is NaN for a joint no believed-state
/// channel covers.
struct TraceJointSample {
  double command_rad = kNoValue;
  double believed_rad = kNoValue;
  double true_rad = kNoValue;
};

/// One sample of everything but the joints. Angles are the true gaze errors: the angle
/// between an eye's true optical axis and the ray from its true optical centre to its target
/// point. The dominant eye's target point is target_W_m: the gaze loop's commanded point
/// (GazeStatus::target_W_m), except while pursuing a named target object: the point of that
/// object the dominant eye's true axis met when pursuit began, moving with the object; and
/// without a gaze loop: the named object's true centre. The verging eye's target point is where the
/// dominant eye's true axis meets the scene (GroundTruth::cast_ray); when it meets nothing, the
/// point of that axis closest to target_W_m. NaN where there is no target.
struct TraceRow {
  double time_s = 0.0;  ///< Since the recorder's first cycle (the run's start).
  bool disparity_valid = false;
  double disparity_px = kNoValue;
  double disparity_confidence = 0.0;
  bool gaze_status = false;  ///< A GazeStatus was read (a gaze loop runs).
  control::GazeAction action = control::GazeAction::kHold;
  bool saccade_active = false;
  std::array<double, 3> target_W_m{kNoValue, kNoValue, kNoValue};
  double dominant_gaze_error_deg = kNoValue;
  double verging_gaze_error_deg = kNoValue;
  double true_gaze_error_deg = kNoValue;  ///< The larger of the two (the one there is).
  /// The disparity the SSM should measure at the retinas' centres (x_left - x_right, level-0
  /// px): the point the dominant eye's true axis meets, projected into the verging camera.
  double true_disparity_px = kNoValue;
  /// The verging eye's view of its target point is blocked by another scene object, or the
  /// dominant eye's axis meets an object other than the named target object.
  bool target_occluded = false;
  /// Where the robot believes it looks (GazeStatus) and where it truly looks: the midpoint of
  /// the shortest segment between the eyes' true axes, valid when they converge in front of
  /// both eyes.
  std::array<double, 3> believed_fixation_W_m{kNoValue, kNoValue, kNoValue};
  bool believed_fixation_valid = false;
  std::array<double, 3> true_fixation_W_m{kNoValue, kNoValue, kNoValue};
  bool true_fixation_valid = false;
  double fixation_error_m = kNoValue;  ///< |believed - true| when both are valid.
  /// Which of Trace::visit_objects the dominant eye's true optical axis meets first (its index),
  /// -1 for none of them.
  int axis_object = -1;
  /// The arm of the newest accepted reach (0 left, 1 right; -1: none yet) and what it does.
  int reach_arm = -1;
  control::ReachPhase reach_phase = control::ReachPhase::kIdle;
  /// Its fingertips' midpoint from the believed joints (ArmStatus) and its distance to the reach
  /// target (the stereo estimate).
  std::array<double, 3> gripper_W_m{kNoValue, kNoValue, kNoValue};
  double gripper_distance_m = kNoValue;
  /// The same point from the true joints, and its signed distance to the target object's
  /// surface (GroundTruth::distance_to_object_m; NaN without a named target object).
  std::array<double, 3> true_gripper_W_m{kNoValue, kNoValue, kNoValue};
  double true_gripper_surface_m = kNoValue;
};

/// The newest reach as the trace saw it (the arms' ArmStatus against the ground truth).
struct ReachRecord {
  bool accepted = false;        ///< A reach was accepted (ArmStatus::command_ns set).
  int arm = -1;                 ///< 0 left, 1 right.
  double command_s = kNoValue;  ///< When it was accepted, since the start.
  double touch_s = kNoValue;    ///< When the touch sensor stopped it.
  /// The target the arm reached for: the head's stereo estimate for a fixation target.
  std::array<double, 3> estimate_W_m{kNoValue, kNoValue, kNoValue};
  /// Where the dominant eye's true optical axis met the target object at the command (ground
  /// truth); NaN when it met something else or nothing.
  std::array<double, 3> true_target_W_m{kNoValue, kNoValue, kNoValue};
  double estimated_target_error_m = kNoValue;  ///< |estimate - true_target|.
  /// At the touch: |the gap| between the gripper's true contact geometry (what its touch sensor
  /// covers) and the target object's surface (GroundTruth::end_effector_gap_m).
  double touch_position_error_m = kNoValue;
  control::ReachPhase final_phase = control::ReachPhase::kIdle;
  /// A reach was refused (the arms' message), the last one.
  bool refused = false;
  std::string refusal;
};

/// Both eyes rendered at one time by the ground truth (rig cameras at their intrinsics).
struct KeyFrame {
  double time_s = 0.0;  ///< When it was rendered (the first sample at or after the asked time).
  std::string camera;
  hal::Image image;
};

/// A recorded run. Joints are stored row-major: rows.size() x joint_names.size().
struct Trace {
  std::vector<std::string> joint_names;  ///< Rig order.
  int dominant_pan_joint = -1;           ///< Index into joint_names; -1 if not given.
  int verging_pan_joint = -1;
  /// The scene objects whose visits are recorded (TraceRow::axis_object).
  std::vector<std::string> visit_objects;
  std::vector<TraceRow> rows;
  std::vector<TraceJointSample> joints;
  std::vector<KeyFrame> key_frames;
  ReachRecord reach;
  /// The preallocated rows ran out (kMaxTraceRows): samples after the last row were dropped.
  bool truncated = false;
  /// What went wrong while recording without stopping it (a key frame that could not render).
  std::vector<std::string> problems;

  std::size_t joint_count() const { return joint_names.size(); }
  std::span<const TraceJointSample> joints_at(std::size_t row) const {
    return std::span<const TraceJointSample>(joints).subspan(row * joint_count(), joint_count());
  }
  /// Appends a row and its joints (joint_count() of them). Throws std::invalid_argument
  /// otherwise. For the recorder and for tests that build traces by hand.
  void add_row(const TraceRow& row, std::span<const TraceJointSample> joint_samples);
};

/// Rows beyond this are not recorded (with the joints, about 400 MB for the 15-joint rig).
inline constexpr std::size_t kMaxTraceRows = std::size_t{1} << 20;

/// A believed-state channel and where its joints sit in rig order: its frame's state i is rig
/// joint rig_indices[i].
struct BelievedStateSource {
  const hal::SeqlockChannel<control::JointStateFrame>* channel = nullptr;
  std::vector<int> rig_indices;
};

/// What the recorder reads. Channels and the ground truth must outlive it.
struct TraceSources {
  std::vector<std::string> joint_names;  ///< Rig order (the targets' order).
  const hal::SeqlockChannel<control::JointTargetFrame>* targets = nullptr;
  std::vector<BelievedStateSource> believed;
  /// Null for a task without a gaze loop.
  const hal::SeqlockChannel<control::GazeStatus>* gaze = nullptr;
  /// The SSM's summaries, for the measured disparity; null: GazeStatus's disparity is used.
  const hal::SeqlockChannel<perception::SsmSummary>* ssm = nullptr;
  sim::GroundTruth* truth = nullptr;
  std::string dominant_camera;
  std::string verging_camera;
  /// The verging camera's focal length and side, for the true disparity (TraceRow).
  double verging_focal_px = 0.0;
  bool verging_eye_is_right = true;
  /// The eyes' pan joints (names in joint_names), for the saccade and neck-rule metrics; may be
  /// empty.
  std::string dominant_pan_joint;
  std::string verging_pan_joint;
  /// The scene object the run is about (may be empty): the dominant eye's target while
  /// pursuing or without a gaze loop, and what the dominant axis may meet without occlusion.
  std::string target_object;
  /// Times (s since the start) at which both eyes are rendered.
  std::vector<double> key_frame_times_s;
  /// Scene objects whose visits by the dominant eye's axis are recorded (may be empty).
  std::vector<std::string> visit_objects;
  /// The arms' status (null: no arm loop) and their chains ([0] left, [1] right) with fingers, to
  /// place the true fingertips.
  const hal::SeqlockChannel<control::ArmStatus>* arms = nullptr;
  std::array<std::optional<control::ArmChain>, 2> arm_chains;
};

/// Records a Trace at the control rate. Evaluation, not control: update() reads the ground
/// truth (which takes a mutex), casts rays and renders key frames, so it allocates and locks
/// (allocates_in_update() is true); the rows themselves are preallocated at configure() for
/// duration x rate (at most kMaxTraceRows), after which it stops and marks the trace truncated.
/// Rendering a key frame under the realtime executor may make a camera skip one grab (the
/// renderer is shared; cameras never wait for it). Read trace() once the executor has stopped.
class TraceRecorder final : public hal::Loop {
 public:
  /// Throws std::invalid_argument for a missing channel or ground truth, an empty camera name,
  /// a believed source whose indices are out of range, a pan joint not in joint_names, or a
  /// non-positive rate or duration.
  TraceRecorder(TraceSources sources, double rate_hz, double duration_s);

  const std::string& name() const override { return name_; }
  /// Reserves the rows; checks the cameras, joints and target object exist in the ground truth
  /// (throws std::out_of_range naming the one that does not).
  void configure() override;
  hal::Status update(const hal::LoopTick& tick) noexcept override;
  bool allocates_in_update() const override { return true; }

  const Trace& trace() const { return trace_; }

 private:
  hal::Status record(const hal::LoopTick& tick);
  void record_arms(TraceRow& row, const sim::RayHit& dominant_hit);
  void render_key_frames(double time_s);

  std::string name_ = "trace";
  TraceSources sources_;
  std::size_t capacity_rows_ = 0;
  Trace trace_;
  std::vector<TraceJointSample> scratch_;
  std::vector<bool> key_frame_done_;
  bool started_ = false;
  std::int64_t start_ns_ = 0;
  control::JointTargetFrame targets_{};
  std::vector<control::JointStateFrame> believed_frames_;  // The last good frame per source.
  // Pursuit's target point in the target object's frame: where the dominant eye's true axis met
  // the object when pursuit began.
  bool pursuit_anchored_ = false;
  Eigen::Vector3d pursuit_anchor_O_ = Eigen::Vector3d::Zero();
  control::GazeStatus status_{};
  perception::SsmSummary summary_{};
  control::ArmStatus arm_status_{};
  std::int64_t last_reach_command_ns_ = 0;
};

/// The reach phase's name as trace.csv and summary.json write it.
const char* reach_phase_name(control::ReachPhase phase);

/// trace.csv: a header row whose names carry their units (time_s, <joint>_command_rad, ...,
/// disparity_px, ...), one row per sample; NaN is written as "nan", booleans as 0/1, the gaze
/// action as hold/fixate/saccade/pursue (empty without a gaze loop).
std::string trace_csv(const Trace& trace);

/// The file name a key frame is staged under: key_<time, ms>ms_<camera>.png.
std::string key_frame_file_name(const KeyFrame& frame);

/// Stages trace.csv and the key frames' PNGs in `out`. Throws OutputError (or ImageFileError)
/// on any failed write or encoding.
void stage_trace(OutputDirectory& out, const Trace& trace);

/// The gaze action's name as trace.csv and summary.json write it.
const char* gaze_action_name(control::GazeAction action);

}  // namespace cambio::app
