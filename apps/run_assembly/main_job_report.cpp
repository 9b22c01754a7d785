#include "main_job.hpp"

#include "cambio/canopen/can_joint_group.hpp"
#include "cambio/hal/camera_faults.hpp"
#include "cambio/ros2/ros2_bridge.hpp"
#include "cambio/sim/rendered_views.hpp"

// What MainJob reports after a run: the loops' counters and last statuses (MainJobResult) and
// each camera's newest frame.

namespace cambio::app {
namespace {

// One report per socketcan group, in rig order.
std::vector<CanGroupReport> can_group_reports(const hal::HardwareInfo& hardware,
                                              const hal::BackendOffers& offers) {
  std::vector<CanGroupReport> reports;
  const auto can_groups = offers.all<const canopen::CanJointGroup>();
  for (const auto& group : hardware.groups) {
    for (const canopen::CanJointGroup* can_group : can_groups) {
      if (can_group->info().name == group.name) {
        const canopen::HomingError error = can_group->last_homing_error();
        reports.push_back({group.name, can_group->counters(), can_group->homing_records(),
                           error.node_id != 0 ? error.text.data() : ""});
      }
    }
  }
  return reports;
}

}  // namespace

void MainJob::collect(MainJobResult& result) {
  result.realtime = realtime_;
  result.loops = executor_->statistics();
  result.camera_frames = camera_loop_->frames_grabbed();
  if (ros2_bridge_) result.ros2 = ros2_bridge_->counts();
  result.stereo_pairs = camera_loop_->pairs_published();
  for (const auto& joint_loop : joint_loops_) {
    result.watchdog_cycles += joint_loop.loop->stale_cycles();
    result.startup_hold_cycles += joint_loop.loop->awaiting_targets_cycles();
    result.fault_hold_cycles += joint_loop.loop->fault_hold_cycles();
    result.fault_recoveries += joint_loop.loop->fault_recoveries();
    control::JointStateFrame states;
    if (joint_loop.states->read(states)) result.fault_latched_at_end |= states.fault_latched;
  }
  for (const hal::CameraFaults* cameras : offers_.all<const hal::CameraFaults>()) {
    for (std::string& fault : cameras->camera_faults()) {
      result.camera_faults.push_back(std::move(fault));
    }
  }
  result.fault_latched_at_end |= !result.camera_faults.empty();
  if (gaze_loop_ != nullptr) result.tracking.push_back(gaze_loop_->tracking().report());
  if (arm_loop_) result.tracking.push_back(arm_loop_->tracking().report());
  if (pose_hold_ != nullptr) result.tracking.push_back(pose_hold_->tracking().report());
  if (perception_loop_) result.mismatched_stereo_pairs = perception_loop_->mismatched_pairs();
  if (const auto* summaries = ssm_summaries()) {
    perception::SsmSummary summary;
    if (summaries->read(summary)) result.perception = summary;
  }
  if (perception_link_) result.perception_link = perception_link_->counts();
  if (gaze_loop_ != nullptr) {
    control::GazeStatus status;
    if (gaze_loop_->status().read(status)) result.gaze = status;
    result.gaze_rejected_commands = gaze_loop_->rejected_commands();
    result.gaze_corrections = gaze_loop_->corrections();
    result.gaze_measurements = gaze_loop_->measurements();
    result.gaze_held_jumps = gaze_loop_->held_jumps();
    result.gaze_occlusion_rejections = gaze_loop_->occlusion_rejections();
    result.gaze_doubtful_departures = gaze_loop_->doubtful_departures();
    result.gaze_faint_steps = gaze_loop_->faint_steps();
    result.gaze_pursuit_region_frames = gaze_loop_->pursuit_region_frames();
    result.gaze_anchor_returns = gaze_loop_->anchor_returns();
    result.gaze_reanchors = gaze_loop_->reanchors();
    result.gaze_false_anchors = gaze_loop_->false_anchors();
    if (script_) {
      result.script_start_ns = script_->start_ns();
      for (const std::int64_t sent_ns : script_->sent_ns()) {
        result.command_sent_s.push_back(
            sent_ns < 0 ? -1.0 : static_cast<double>(sent_ns - script_->start_ns()) * 1e-9);
      }
    }
  }
  if (behaviour_loop_) {
    BehaviourReport report;
    report.name = experiment_.behaviour->name;
    report.plugins = plugins_->paths();
    report.steps = behaviour_loop_->steps();
    report.status = behaviour_loop_->status();
    report.failed = behaviour_loop_->failed();
    report.error = behaviour_loop_->error();
    result.behaviour = std::move(report);
  }
  if (arm_loop_) {
    control::ArmStatus status;
    if (arm_loop_->status().read(status)) result.arms = status;
    for (int side = 0; side < 2; ++side) {
      result.arm_present[static_cast<std::size_t>(side)] = arm_loop_->arm(side) != nullptr;
    }
  }
  result.can_groups = can_group_reports(hardware_, offers_);
  result.renderer = renderer();
}

std::vector<hal::Image> MainJob::last_frames() {
  std::vector<const hal::Image*> frames(cameras_.size(), nullptr);
  if (camera_loop_->has_stereo()) {
    // The loops have stopped: this thread may take the stereo channel's reader side.
    auto& pairs = camera_loop_->stereo_frames();
    pairs.acquire();
    const auto& stereo = *hardware_.stereo;
    frames[camera_index(stereo.left_camera)] = &pairs.front().left;
    frames[camera_index(stereo.right_camera)] = &pairs.front().right;
  }
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (frames[i] != nullptr) continue;
    auto& channel = camera_loop_->frames(i);
    channel.acquire();
    frames[i] = &channel.front();
  }
  std::vector<hal::Image> images;
  images.reserve(frames.size());
  const auto renderers = offers_.all<sim::RenderedViews>();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    images.push_back(*frames[i]);
    if (frames[i]->sequence == 0) continue;
    for (sim::RenderedViews* views : renderers) {
      hal::Image whole;
      if (!views->render_whole_frame(hardware_.cameras[i].name, whole)) continue;
      whole.sequence = frames[i]->sequence;
      images.back() = std::move(whole);
      break;
    }
  }
  return images;
}

}  // namespace cambio::app
