#pragma once

// Records a run's Trace (trace.hpp) at the control rate from the control side's channels and the
// simulator's ground truth.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cambio/control/arm_chain.hpp"
#include "cambio/control/arm_command.hpp"
#include "cambio/control/gaze_command.hpp"
#include "cambio/control/joint_frames.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/perception/sensory_servo.hpp"
#include "cambio/sim/ground_truth.hpp"
#include "trace.hpp"

namespace cambio::app {

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
  // record() in steps, in the order they read the channels and the ground truth
  // (trace_recorder.cpp; the arms in trace_recorder_reach.cpp).
  hal::Status record(const hal::LoopTick& tick);
  void render_key_frames(double time_s);
  void read_joints();
  void read_gaze(TraceRow& row);
  Eigen::Vector3d dominant_target_W(const TraceRow& row);
  void record_arms(TraceRow& row, const sim::RayHit& dominant_hit);
  void note_refusal();
  int reaching_arm() const;
  void record_true_gripper(TraceRow& row, const control::ArmChain& chain);
  void start_reach(int side, const control::ArmStatus::Arm& arm, const sim::RayHit& dominant_hit);
  void record_touch(const control::ArmStatus::Arm& arm, const control::ArmChain& chain);

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

}  // namespace cambio::app
