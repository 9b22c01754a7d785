#include <time.h>

#include <iostream>
#include <memory>

#include "cambio/ros2/perception_link.hpp"
#include "cambio/ros2/ros2_bridge.hpp"
#include "cambio/ros2/urdf_export.hpp"
#include "main_job.hpp"
#include "ros2_diagnostics.hpp"

// MainJob's bridge to ROS 2: the joint loops' published states as /joint_states and /tf (and
// /clock on simulated time), the stereo pair's images with their camera_info, sampled on the
// bridge's own threads; the cameras' mounts on /tf_static.

namespace cambio::app {
namespace {

std::int64_t clock_ns(clockid_t clock) {
  timespec now{};
  clock_gettime(clock, &now);
  return std::int64_t{now.tv_sec} * 1'000'000'000 + now.tv_nsec;
}

// A ROS joint trajectory (its sizes checked by the bridge) to the loops through RobotActions.
std::string send_trajectory(RobotActions& actions, const ros2::TrajectoryMessage& message) {
  control::JointTrajectory trajectory;
  const std::size_t joints = message.joint_names.size();
  trajectory.joint_count = static_cast<int>(joints);
  trajectory.point_count = static_cast<int>(message.time_from_start_s.size());
  trajectory.has_velocities = !message.velocities_rad_s.empty();
  for (std::size_t k = 0; k < message.time_from_start_s.size(); ++k) {
    trajectory.time_from_start_s[k] = message.time_from_start_s[k];
    for (std::size_t j = 0; j < joints; ++j) {
      trajectory.positions_rad[k][j] = message.positions_rad[k * joints + j];
      if (trajectory.has_velocities) {
        trajectory.velocities_rad_s[k][j] = message.velocities_rad_s[k * joints + j];
      }
    }
  }
  const behaviour::ActionResult result = actions.follow_trajectory(message.joint_names, trajectory);
  return result.sent ? std::string() : result.message;
}

}  // namespace

void MainJob::build_ros2_bridge() {
  if (!experiment_.ros2) return;
  const config::Ros2Config& config = *experiment_.ros2;
  ros2::BridgeSettings settings;
  settings.domain_id = static_cast<std::uint32_t>(config.domain_id);
  settings.joint_states_rate_hz = config.joint_states_hz;
  // ROS time is the Unix epoch's; a wall-clock run's clock is CLOCK_MONOTONIC. A simulated run
  // keeps its own time and says so on /clock.
  settings.publish_clock = config.clock && !realtime_;
  settings.publish_tf = config.tf;
  settings.images_rate_hz = config.images_hz;
  settings.diagnostics_rate_hz = config.diagnostics_hz;
  settings.gaze_rate_hz = gaze_loop_ != nullptr ? config.gaze_hz : 0.0;
  settings.epoch_offset_ns = realtime_ ? clock_ns(CLOCK_REALTIME) - clock_ns(CLOCK_MONOTONIC) : 0;

  // Each joint loop's newest frame, its joints put in rig order; the stamp is the newest of them.
  struct Reader {
    std::vector<const hal::SeqlockChannel<control::JointStateFrame>*> channels;
    std::vector<std::vector<int>> rig_indices;
  };
  auto reader = std::make_shared<Reader>();
  for (const JointLoopSlot& slot : joint_loops_) {
    reader->channels.push_back(slot.states.get());
    reader->rig_indices.push_back(slot.rig_indices);
  }
  // Called from the bridge's joint-state and command threads: its scratch frame is its own.
  ros2::JointStatesSampler sampler = [reader](ros2::JointStatesSample& sample) {
    std::int64_t newest_ns = 0;
    control::JointStateFrame frame;
    for (std::size_t k = 0; k < reader->channels.size(); ++k) {
      if (reader->channels[k]->version() == 0 || !reader->channels[k]->read(frame)) {
        return false;  // A loop that has not published yet (or kept every read torn).
      }
      const std::vector<int>& indices = reader->rig_indices[k];
      const auto count = std::min(indices.size(), static_cast<std::size_t>(frame.count));
      for (std::size_t j = 0; j < count; ++j) {
        const hal::JointState& state = frame.states[j];
        const auto rig = static_cast<std::size_t>(indices[j]);
        sample.position_rad[rig] = state.position_rad;
        sample.velocity_rad_s[rig] = state.velocity_rad_s;
        sample.effort_nm[rig] = state.effort_nm;
      }
      newest_ns = std::max(newest_ns, frame.stamp_ns);
    }
    sample.stamp_ns = newest_ns;
    return true;
  };
  ros2::BridgeSources sources;
  sources.joint_names = joint_order_;
  sources.tf_tree = ros2::make_tf_tree(hardware_, joint_order_);
  sources.joint_states = std::move(sampler);
  sources.robot_description = ros2::make_urdf(hardware_, experiment_.rig.name);
  // On a split run the perception link sends every pair on the same topics.
  if (config.images_hz > 0.0 && hardware_.stereo && !perception_remote_) {
    sources.stereo_images = claim_observed_stereo_frames();
    sources.stereo_cameras = {hardware_.cameras[camera_index(hardware_.stereo->left_camera)],
                              hardware_.cameras[camera_index(hardware_.stereo->right_camera)]};
  }
  if (config.diagnostics_hz > 0.0) {
    DiagnosticsInputs inputs;
    inputs.executor = executor_.get();
    for (const JointLoopSlot& slot : joint_loops_) {
      inputs.joint_loops.push_back({slot.loop.get(), slot.states.get(), slot.rig_indices});
    }
    inputs.joint_names = joint_order_;
    for (const hal::JointGroupInfo& group : hardware_.groups) {
      for (std::size_t j = 0; j < group.joints.size(); ++j)
        inputs.joint_groups.push_back(group.name);
    }
    inputs.can_groups = offers_.all<const canopen::CanJointGroup>();
    inputs.perception_link = perception_link_.get();
    sources.diagnostics = make_diagnostics_sampler(std::move(inputs));
  }
  if (gaze_loop_ != nullptr && config.gaze_hz > 0.0) {
    sources.gaze = make_gaze_sampler(*gaze_loop_);
  }
  if (config.commands && actions_) {
    // Through the same actions as the console and behaviours: the same checks, one writer.
    sources.look_at = [actions = actions_.get()](const Eigen::Vector3d& p_base_m) {
      const behaviour::ActionResult result = actions->look_at_point(p_base_m);
      return result.sent ? std::string() : result.message;
    };
    sources.joint_trajectory = [actions = actions_.get()](const ros2::TrajectoryMessage& message) {
      return send_trajectory(*actions, message);
    };
    sources.trajectory_max_points = control::JointTrajectory::kMaxPoints;
    sources.trajectory_max_joints = control::JointTrajectory::kMaxJoints;
  }
  ros2_bridge_ = std::make_unique<ros2::Ros2Bridge>(settings, std::move(sources));
}

void MainJob::build_perception_link() {
  if (!perception_remote_) return;
  const config::Ros2Config& config = *experiment_.ros2;
  ros2::RobotPerceptionLinkSettings settings;
  settings.domain_id = static_cast<std::uint32_t>(config.domain_id);
  settings.epoch_offset_ns = clock_ns(CLOCK_REALTIME) - clock_ns(CLOCK_MONOTONIC);
  settings.link_timeout_s = config.link_timeout_s;
  // A result older than the outage that defines a lost link is not worth servoing on.
  settings.max_result_age_s = config.link_timeout_s;
  const hal::Clock& clock = executor_->clock();
  perception_link_ = std::make_unique<ros2::RobotPerceptionLink>(
      settings, [&clock] { return clock.now_ns(); }, camera_loop_->stereo_frames(),
      std::array<hal::CameraInfo, 2>{
          hardware_.cameras[camera_index(hardware_.stereo->left_camera)],
          hardware_.cameras[camera_index(hardware_.stereo->right_camera)]},
      remote_requests_, remote_summaries_);
}

void MainJob::wait_for_perception_host() {
  const config::Ros2Config& config = *experiment_.ros2;
  std::cerr << "cambio run: waiting up to " << config.host_wait_s
            << " s for the perception host (cambio node perception) on ROS 2 domain "
            << config.domain_id << "\n";
  if (!perception_link_->wait_for_host(config.host_wait_s)) {
    throw std::runtime_error(
        "no perception host answered on ROS 2 domain " + std::to_string(config.domain_id) +
        " within " + std::to_string(config.host_wait_s) +
        " s (ros2.host_wait_s): start `cambio node perception " + experiment_.source_file +
        "` on the perception host, on the same domain and network (CYCLONEDDS_URI)");
  }
}

const hal::SeqlockChannel<perception::SsmSummary>* MainJob::ssm_summaries() const {
  if (perception_remote_) return &remote_summaries_;
  return perception_loop_ ? &perception_loop_->summaries() : nullptr;
}

hal::SeqlockChannel<perception::SsmRequest>* MainJob::ssm_requests() {
  if (perception_remote_) return &remote_requests_;
  return perception_loop_ ? &perception_loop_->requests() : nullptr;
}

hal::TripleBuffer<hal::StereoFrame>* MainJob::claim_observed_stereo_frames() {
  if (observed_stereo_claimed_ || !camera_loop_ || !camera_loop_->has_stereo()) return nullptr;
  observed_stereo_claimed_ = true;
  return &camera_loop_->observed_stereo_frames();
}

bool MainJob::set_remote_command_handler(std::function<std::string(const std::string&)> handler) {
  if (!ros2_bridge_ || !experiment_.ros2->commands || !actions_) return false;
  ros2_bridge_->set_command_handler(std::move(handler));
  return true;
}

}  // namespace cambio::app
