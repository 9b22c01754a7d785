#include "cambio/ros2/ros2_bridge.hpp"

#include <dds/dds.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <stdexcept>
#include <thread>
#include <utility>

#include "geometry_msgs/msg/PointStamped.h"

#include "cambio/ros2/ros_time.hpp"
#include "dds_entities.hpp"
#include "diagnostic_msgs/msg/DiagnosticArray.h"
#include "link_messages.hpp"
#include "node_graph.hpp"
#include "rosgraph_msgs/msg/Clock.h"
#include "sensor_msgs/msg/CameraInfo.h"
#include "sensor_msgs/msg/Image.h"
#include "sensor_msgs/msg/JointState.h"
#include "std_msgs/msg/String.h"
#include "tf2_msgs/msg/TFMessage.h"
#include "trajectory_msgs/msg/JointTrajectory.h"

namespace cambio::ros2 {
namespace {

using dds::checked;
using dds::make_reader;
using dds::make_writer;
using dds::Qos;

// More joints than any robot this stack drives; a bound keeps a message's size known.
constexpr std::size_t kMaxJoints = 256;
constexpr double kMaxRateHz = 1000.0;

void set_transform(geometry_msgs_msg_dds__Transform_& out, const FrameTransform& in) {
  out.translation = {in.translation_m[0], in.translation_m[1], in.translation_m[2]};
  out.rotation = {in.rotation_xyzw[0], in.rotation_xyzw[1], in.rotation_xyzw[2],
                  in.rotation_xyzw[3]};
}

void check_rate(double rate_hz, const char* what) {
  if (!(rate_hz >= 0.0 && rate_hz <= kMaxRateHz)) {
    throw std::invalid_argument(std::string("ROS 2 bridge: ") + what + " rate " +
                                std::to_string(rate_hz) + " Hz, expected 0 to 1000");
  }
}

// sensor_msgs/CameraInfo of an unrectified camera: the plumb-bob model, R the identity, P the
// intrinsics with no stereo shift (the eyes verge, so no pair of them is rectified; their poses
// are on /tf).
void fill_camera_info(sensor_msgs_msg_dds__CameraInfo_& out, const hal::CameraInfo& camera,
                      std::array<double, 5>& distortion) {
  const hal::CameraIntrinsics& in = camera.intrinsics;
  out.height = static_cast<std::uint32_t>(in.height_px);
  out.width = static_cast<std::uint32_t>(in.width_px);
  out.distortion_model = const_cast<char*>("plumb_bob");
  distortion = camera.distortion.opencv_order();
  out.d = dds_sequence_double{5, 5, distortion.data(), false};
  const double k[9] = {
      in.focal_x_px, 0, in.principal_x_px, 0, in.focal_y_px, in.principal_y_px, 0, 0, 1};
  const double r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double p[12] = {
      in.focal_x_px, 0, in.principal_x_px, 0, 0, in.focal_y_px, in.principal_y_px, 0, 0, 0, 1, 0};
  std::copy(std::begin(k), std::end(k), out.k);
  std::copy(std::begin(r), std::end(r), out.r);
  std::copy(std::begin(p), std::end(p), out.p);
}

}  // namespace

// The participant and its writers; deleting the participant deletes them (writers linger for
// reliable readers' acknowledgements, Cyclone's WriterLingerDuration).
struct Ros2Bridge::Dds {
  dds_entity_t participant = 0;
  dds_entity_t joint_states = 0;
  dds_entity_t clock = 0;
  dds_entity_t tf = 0;
  dds_entity_t tf_static = 0;
  std::array<dds_entity_t, 2> images{};
  std::array<dds_entity_t, 2> camera_infos{};
  dds_entity_t robot_description = 0;
  dds_entity_t diagnostics = 0;
  dds_entity_t gaze_fixation = 0;
  dds_entity_t gaze_status = 0;
  dds_entity_t look_at = 0;     // Reader.
  dds_entity_t command = 0;     // Reader: console lines.
  dds_entity_t trajectory = 0;  // Reader: joint trajectories (0: not subscribed).
  dds_entity_t refusals = 0;    // Writer.
  dds_entity_t discovery = 0;   // Writer: ros_discovery_info.
  dds_entity_t waitset = 0;     // The command thread's: new commands, or stop.
  dds_entity_t stop_guard = 0;
  std::vector<char*> names;  // Into the sources' joint names; the message borrows them.
  // One per joint, their frame names borrowed from the sources' tf tree.
  std::vector<geometry_msgs_msg_dds__TransformStamped_> joint_transforms;
  std::array<sensor_msgs_msg_dds__CameraInfo_, 2> camera_info{};
  std::array<std::array<double, 5>, 2> distortion{};
  ~Dds() {
    if (participant > 0) dds_delete(participant);
  }
};

Ros2Bridge::Ros2Bridge(const BridgeSettings& settings, BridgeSources sources)
    : settings_(settings), sources_(std::move(sources)) {
  const std::size_t n = sources_.joint_names.size();
  if (n > kMaxJoints) {
    throw std::invalid_argument("ROS 2 bridge: " + std::to_string(n) + " joints, at most " +
                                std::to_string(kMaxJoints));
  }
  check_rate(settings_.joint_states_rate_hz, "joint states");
  check_rate(settings_.images_rate_hz, "images");
  check_rate(settings_.diagnostics_rate_hz, "diagnostics");
  check_rate(settings_.gaze_rate_hz, "gaze");
  for (const TfJoint& joint : sources_.tf_tree.joints) {
    if (joint.position_index >= n) {
      throw std::invalid_argument("ROS 2 bridge: tf joint '" + joint.child_frame +
                                  "' has no position in the joint states");
    }
  }
  sample_.position_rad.assign(n, 0.0);
  sample_.velocity_rad_s.assign(n, 0.0);
  sample_.effort_nm.assign(n, 0.0);
  command_sample_ = sample_;

  dds_ = std::make_unique<Dds>();
  dds_->participant = checked(dds_create_participant(settings_.domain_id, nullptr, nullptr),
                              "join the DDS domain (check CYCLONEDDS_URI and the domain id)");
  const dds_entity_t participant = dds_->participant;
  const Qos state(DDS_RELIABILITY_RELIABLE, 10);
  if (settings_.joint_states_rate_hz > 0.0) {
    dds_->joint_states =
        make_writer(participant, sensor_msgs_msg_dds__JointState__desc, "/joint_states", state);
    if (settings_.publish_clock) {
      dds_->clock = make_writer(participant, rosgraph_msgs_msg_dds__Clock__desc, "/clock", state);
    }
    if (settings_.publish_tf) {
      dds_->tf = make_writer(participant, tf2_msgs_msg_dds__TFMessage__desc, "/tf",
                             Qos(DDS_RELIABILITY_RELIABLE, 100));
    }
  }
  if (settings_.publish_tf) {
    dds_->tf_static = make_writer(participant, tf2_msgs_msg_dds__TFMessage__desc, "/tf_static",
                                  Qos(DDS_RELIABILITY_RELIABLE, 1, DDS_DURABILITY_TRANSIENT_LOCAL));
  }
  if (!sources_.robot_description.empty()) {
    dds_->robot_description =
        make_writer(participant, std_msgs_msg_dds__String__desc, "/robot_description",
                    Qos(DDS_RELIABILITY_RELIABLE, 1, DDS_DURABILITY_TRANSIENT_LOCAL));
  }
  if (settings_.images_rate_hz > 0.0 && sources_.stereo_images != nullptr) {
    const Qos sensor_data(DDS_RELIABILITY_BEST_EFFORT, 5);
    for (std::size_t eye = 0; eye < 2; ++eye) {
      const hal::CameraInfo& camera = sources_.stereo_cameras[eye];
      optical_frames_[eye] = camera.name + "_optical_frame";
      dds_->images[eye] = make_writer(participant, sensor_msgs_msg_dds__Image__desc,
                                      "/" + camera.name + "/image_raw", sensor_data);
      dds_->camera_infos[eye] = make_writer(participant, sensor_msgs_msg_dds__CameraInfo__desc,
                                            "/" + camera.name + "/camera_info", sensor_data);
      fill_camera_info(dds_->camera_info[eye], camera, dds_->distortion[eye]);
      dds_->camera_info[eye].header.frame_id = optical_frames_[eye].data();
    }
  }
  if (settings_.diagnostics_rate_hz > 0.0 && sources_.diagnostics) {
    dds_->diagnostics = make_writer(participant, diagnostic_msgs_msg_dds__DiagnosticArray__desc,
                                    "/diagnostics", state);
  }
  if (settings_.gaze_rate_hz > 0.0 && sources_.gaze) {
    dds_->gaze_fixation = make_writer(participant, geometry_msgs_msg_dds__PointStamped__desc,
                                      "/cambio/gaze/fixation", state);
    dds_->gaze_status = make_writer(participant, diagnostic_msgs_msg_dds__DiagnosticStatus__desc,
                                    "/cambio/gaze/status", state);
  }
  if (sources_.look_at) {
    dds_->refusals =
        make_writer(participant, std_msgs_msg_dds__String__desc, "/cambio/refusals", state);
    const std::string what = "create the command waitset";
    dds_->look_at = make_reader(participant, geometry_msgs_msg_dds__PointStamped__desc,
                                "/cambio/look_at", state);
    dds_->command =
        make_reader(participant, std_msgs_msg_dds__String__desc, "/cambio/command", state);
    if (sources_.joint_trajectory) {
      dds_->trajectory = make_reader(participant, trajectory_msgs_msg_dds__JointTrajectory__desc,
                                     "/cambio/joint_trajectory", state);
    }
    dds_->waitset = checked(dds_create_waitset(participant), what);
    dds_->stop_guard = checked(dds_create_guardcondition(participant), what);
    const dds_entity_t readable =
        checked(dds_create_readcondition(dds_->look_at, DDS_ANY_STATE), what);
    const dds_entity_t command_readable =
        checked(dds_create_readcondition(dds_->command, DDS_ANY_STATE), what);
    if (dds_waitset_attach(dds_->waitset, readable, 0) != DDS_RETCODE_OK ||
        dds_waitset_attach(dds_->waitset, command_readable, 0) != DDS_RETCODE_OK ||
        dds_waitset_attach(dds_->waitset, dds_->stop_guard, 0) != DDS_RETCODE_OK ||
        (dds_->trajectory != 0 &&
         dds_waitset_attach(
             dds_->waitset,
             checked(dds_create_readcondition(dds_->trajectory, DDS_ANY_STATE), what),
             0) != DDS_RETCODE_OK)) {
      throw std::runtime_error("ROS 2: cannot " + what);
    }
  }
  for (std::string& name : sources_.joint_names) dds_->names.push_back(name.data());
  for (TfJoint& joint : sources_.tf_tree.joints) {
    geometry_msgs_msg_dds__TransformStamped_ transform{};
    transform.header.frame_id = joint.parent_frame.data();
    transform.child_frame_id = joint.child_frame.data();
    dds_->joint_transforms.push_back(transform);
  }
  publish_discovery_info();
}

Ros2Bridge::~Ros2Bridge() {
  stop();
}

void Ros2Bridge::start() {
  if (started_) return;
  started_ = true;
  if (dds_->tf_static != 0) publish_tf_static();
  if (dds_->robot_description != 0) {
    const std_msgs_msg_dds__String_ urdf{sources_.robot_description.data()};
    write(dds_->robot_description, &urdf, nullptr);
  }
  if (dds_->joint_states != 0) {
    threads_.emplace_back(
        [this] { run_every(settings_.joint_states_rate_hz, &Ros2Bridge::publish_joint_states); });
  }
  if (dds_->images[0] != 0) {
    threads_.emplace_back(
        [this] { run_every(settings_.images_rate_hz, &Ros2Bridge::publish_images); });
  }
  if (dds_->diagnostics != 0) {
    threads_.emplace_back(
        [this] { run_every(settings_.diagnostics_rate_hz, &Ros2Bridge::publish_diagnostics); });
  }
  if (dds_->gaze_status != 0) {
    threads_.emplace_back([this] { run_every(settings_.gaze_rate_hz, &Ros2Bridge::publish_gaze); });
  }
  if (dds_->look_at != 0) threads_.emplace_back([this] { serve_commands(); });
}

void Ros2Bridge::stop() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (dds_->stop_guard != 0) dds_set_guardcondition(dds_->stop_guard, true);
  for (std::thread& thread : threads_) thread.join();
  threads_.clear();
}

BridgeCounts Ros2Bridge::counts() const {
  BridgeCounts counts;
  counts.joint_states = joint_states_sent_.load();
  counts.clock = clock_sent_.load();
  counts.tf = tf_sent_.load();
  counts.images = images_sent_.load();
  counts.camera_infos = camera_infos_sent_.load();
  counts.diagnostics = diagnostics_sent_.load();
  counts.gaze = gaze_sent_.load();
  counts.commands_received = commands_received_.load();
  counts.commands_refused = commands_refused_.load();
  counts.write_errors = write_errors_.load();
  return counts;
}

void Ros2Bridge::run_every(double rate_hz, void (Ros2Bridge::*publish)()) {
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / rate_hz));
  auto next = std::chrono::steady_clock::now();
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    lock.unlock();
    (this->*publish)();
    lock.lock();
    // A late wake-up skips the ticks it missed rather than publishing them in a burst.
    next = std::max(next + period, std::chrono::steady_clock::now());
    wake_.wait_until(lock, next, [this] { return stopping_; });
  }
  lock.unlock();
  (this->*publish)();  // What the run ended with.
}

bool Ros2Bridge::write(std::int32_t writer, const void* message, std::atomic<std::uint64_t>* sent) {
  if (dds_write(writer, message) != DDS_RETCODE_OK) {
    write_errors_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  if (sent != nullptr) sent->fetch_add(1, std::memory_order_relaxed);
  return true;
}

void Ros2Bridge::publish_joint_states() {
  if (!sources_.joint_states(sample_) || sample_.stamp_ns == last_published_stamp_ns_) return;
  last_published_stamp_ns_ = sample_.stamp_ns;
  const RosTime stamp = to_ros_time(sample_.stamp_ns, settings_.epoch_offset_ns);
  const auto n = static_cast<std::uint32_t>(sources_.joint_names.size());
  auto sequence = [n](std::vector<double>& values) {
    return dds_sequence_double{n, n, values.data(), false};
  };
  sensor_msgs_msg_dds__JointState_ message{};
  message.header.stamp = {stamp.sec, stamp.nanosec};
  message.header.frame_id = const_cast<char*>("");  // Joint states name their joints, no frame.
  message.name = dds_sequence_string{n, n, dds_->names.data(), false};
  message.position = sequence(sample_.position_rad);
  message.velocity = sequence(sample_.velocity_rad_s);
  message.effort = sequence(sample_.effort_nm);
  write(dds_->joint_states, &message, &joint_states_sent_);
  if (dds_->clock != 0) {
    const rosgraph_msgs_msg_dds__Clock_ clock{{stamp.sec, stamp.nanosec}};
    write(dds_->clock, &clock, &clock_sent_);
  }
  if (dds_->tf != 0) publish_tf(sample_.stamp_ns);
}

void Ros2Bridge::publish_tf(std::int64_t stamp_ns) {
  const RosTime stamp = to_ros_time(stamp_ns, settings_.epoch_offset_ns);
  for (std::size_t k = 0; k < sources_.tf_tree.joints.size(); ++k) {
    const TfJoint& joint = sources_.tf_tree.joints[k];
    geometry_msgs_msg_dds__TransformStamped_& out = dds_->joint_transforms[k];
    out.header.stamp = {stamp.sec, stamp.nanosec};
    set_transform(out.transform,
                  joint_transform(joint, sample_.position_rad[joint.position_index]));
  }
  const auto n = static_cast<std::uint32_t>(dds_->joint_transforms.size());
  const tf2_msgs_msg_dds__TFMessage_ message{{n, n, dds_->joint_transforms.data(), false}};
  write(dds_->tf, &message, &tf_sent_);
}

void Ros2Bridge::publish_tf_static() {
  // Fixed frames hold for all time; tf ignores a static transform's stamp.
  const RosTime stamp = to_ros_time(0, settings_.epoch_offset_ns);
  std::vector<geometry_msgs_msg_dds__TransformStamped_> transforms;
  for (TfFixed& fixed : sources_.tf_tree.fixed) {
    geometry_msgs_msg_dds__TransformStamped_ transform{};
    transform.header.stamp = {stamp.sec, stamp.nanosec};
    transform.header.frame_id = fixed.parent_frame.data();
    transform.child_frame_id = fixed.child_frame.data();
    set_transform(transform.transform, to_frame_transform(fixed.X_PC));
    transforms.push_back(transform);
  }
  const auto n = static_cast<std::uint32_t>(transforms.size());
  const tf2_msgs_msg_dds__TFMessage_ message{{n, n, transforms.data(), false}};
  write(dds_->tf_static, &message, &tf_sent_);
}

void Ros2Bridge::publish_images() {
  if (!sources_.stereo_images->acquire()) return;
  const hal::StereoFrame& pair = sources_.stereo_images->front();
  publish_image(0, pair.left);
  publish_image(1, pair.right);
}

void Ros2Bridge::publish_image(std::size_t eye, const hal::Image& image) {
  const sensor_msgs_msg_dds__Image_ message = image_message(
      image, optical_frames_[eye], to_ros_time(image.stamp_ns, settings_.epoch_offset_ns));
  if (!write(dds_->images[eye], &message, &images_sent_)) return;
  sensor_msgs_msg_dds__CameraInfo_& info = dds_->camera_info[eye];
  info.header.stamp = message.header.stamp;
  write(dds_->camera_infos[eye], &info, &camera_infos_sent_);
}

namespace {

// A DiagnosticStatus borrowing `entry`'s strings; its key-values go in `values` (kept alive by
// the caller until the message is written).
diagnostic_msgs_msg_dds__DiagnosticStatus_ status_of(
    DiagnosticEntry& entry, std::vector<diagnostic_msgs_msg_dds__KeyValue_>& values) {
  values.clear();
  for (auto& [key, value] : entry.values) values.push_back({key.data(), value.data()});
  diagnostic_msgs_msg_dds__DiagnosticStatus_ status{};
  status.level = static_cast<std::uint8_t>(entry.level);
  status.name = entry.name.data();
  status.message = entry.message.data();
  status.hardware_id = entry.hardware_id.data();
  const auto n = static_cast<std::uint32_t>(values.size());
  status.values = {n, n, values.data(), false};
  return status;
}

}  // namespace

void Ros2Bridge::publish_diagnostics() {
  std::int64_t stamp_ns = 0;
  std::vector<DiagnosticEntry> entries;
  if (!sources_.diagnostics(stamp_ns, entries)) return;
  std::vector<std::vector<diagnostic_msgs_msg_dds__KeyValue_>> values(entries.size());
  std::vector<diagnostic_msgs_msg_dds__DiagnosticStatus_> statuses;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    statuses.push_back(status_of(entries[i], values[i]));
  }
  const RosTime stamp = to_ros_time(stamp_ns, settings_.epoch_offset_ns);
  diagnostic_msgs_msg_dds__DiagnosticArray_ message{};
  message.header.stamp = {stamp.sec, stamp.nanosec};
  message.header.frame_id = const_cast<char*>("");
  const auto n = static_cast<std::uint32_t>(statuses.size());
  message.status = {n, n, statuses.data(), false};
  write(dds_->diagnostics, &message, &diagnostics_sent_);
}

void Ros2Bridge::publish_gaze() {
  GazeSample sample;
  if (!sources_.gaze(sample)) return;
  const RosTime stamp = to_ros_time(sample.stamp_ns, settings_.epoch_offset_ns);
  if (sample.fixation_valid) {
    geometry_msgs_msg_dds__PointStamped_ fixation{};
    fixation.header.stamp = {stamp.sec, stamp.nanosec};
    fixation.header.frame_id = const_cast<char*>("base");
    fixation.point = {sample.fixation_base_m[0], sample.fixation_base_m[1],
                      sample.fixation_base_m[2]};
    write(dds_->gaze_fixation, &fixation, nullptr);
  }
  std::vector<diagnostic_msgs_msg_dds__KeyValue_> values;
  const diagnostic_msgs_msg_dds__DiagnosticStatus_ status = status_of(sample.status, values);
  write(dds_->gaze_status, &status, &gaze_sent_);
}

void Ros2Bridge::publish_discovery_info() {
  bool written = false;
  dds_->discovery = announce_node(
      dds_->participant, settings_.node_name,
      {dds_->joint_states, dds_->clock, dds_->tf, dds_->tf_static, dds_->images[0], dds_->images[1],
       dds_->camera_infos[0], dds_->camera_infos[1], dds_->robot_description, dds_->diagnostics,
       dds_->gaze_fixation, dds_->gaze_status, dds_->refusals},
      {dds_->look_at, dds_->command, dds_->trajectory}, written);
  if (!written) write_errors_.fetch_add(1, std::memory_order_relaxed);
}

void Ros2Bridge::serve_commands() {
  constexpr int kBatch = 16;
  for (;;) {
    {
      const std::lock_guard lock(mutex_);
      if (stopping_) return;
    }
    // Woken by a command or by stop(); the timeout only bounds a missed wake-up.
    dds_waitset_wait(dds_->waitset, nullptr, 0, DDS_MSECS(500));
    void* samples[kBatch] = {};
    dds_sample_info_t infos[kBatch];
    int n = 0;
    while ((n = dds_take(dds_->look_at, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (infos[i].valid_data) handle_look_at(samples[i]);
      }
      dds_return_loan(dds_->look_at, samples, n);
    }
    while ((n = dds_take(dds_->command, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (infos[i].valid_data) handle_command(samples[i]);
      }
      dds_return_loan(dds_->command, samples, n);
    }
    if (dds_->trajectory == 0) continue;
    while ((n = dds_take(dds_->trajectory, samples, infos, kBatch, kBatch)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (infos[i].valid_data) handle_trajectory(samples[i]);
      }
      dds_return_loan(dds_->trajectory, samples, n);
    }
  }
}

void Ros2Bridge::handle_trajectory(const void* joint_trajectory) {
  commands_received_.fetch_add(1, std::memory_order_relaxed);
  const auto& message =
      *static_cast<const trajectory_msgs_msg_dds__JointTrajectory_*>(joint_trajectory);
  const std::string topic = "/cambio/joint_trajectory: ";
  const std::size_t joints = message.joint_names._length;
  const std::size_t points = message.points._length;
  // Sizes first: a remote node's million points are refused before anything is copied.
  if (joints == 0 || joints > sources_.trajectory_max_joints) {
    refuse(topic + std::to_string(joints) + " joint names; a trajectory names 1 to " +
           std::to_string(sources_.trajectory_max_joints));
    return;
  }
  if (points == 0 || points > sources_.trajectory_max_points) {
    refuse(topic + std::to_string(points) + " points; a trajectory has 1 to " +
           std::to_string(sources_.trajectory_max_points));
    return;
  }
  TrajectoryMessage trajectory;
  for (std::size_t j = 0; j < joints; ++j) {
    const char* name = message.joint_names._buffer[j];
    // A joint's name is short; a megabyte one is cut where no joint's name could reach.
    constexpr std::size_t kMaxNameBytes = 256;
    trajectory.joint_names.emplace_back(name != nullptr ? name : "",
                                        name != nullptr ? strnlen(name, kMaxNameBytes) : 0);
  }
  const bool velocities = message.points._buffer[0].velocities._length != 0;
  for (std::size_t k = 0; k < points; ++k) {
    const trajectory_msgs_msg_dds__JointTrajectoryPoint_& point = message.points._buffer[k];
    if (point.positions._length != joints) {
      refuse(topic + "point " + std::to_string(k) + " has " +
             std::to_string(point.positions._length) + " positions for " + std::to_string(joints) +
             " joints");
      return;
    }
    if (point.velocities._length != (velocities ? joints : 0)) {
      refuse(topic + "point " + std::to_string(k) + " has " +
             std::to_string(point.velocities._length) +
             " velocities; give one per joint at every point, or none at all");
      return;
    }
    trajectory.time_from_start_s.push_back(static_cast<double>(point.time_from_start.sec) +
                                           1e-9 * point.time_from_start.nanosec);
    trajectory.positions_rad.insert(trajectory.positions_rad.end(), point.positions._buffer,
                                    point.positions._buffer + joints);
    if (velocities) {
      trajectory.velocities_rad_s.insert(trajectory.velocities_rad_s.end(),
                                         point.velocities._buffer,
                                         point.velocities._buffer + joints);
    }
  }
  const std::string refusal = sources_.joint_trajectory(trajectory);
  if (!refusal.empty()) refuse(topic + refusal);
}

void Ros2Bridge::handle_command(const void* string_message) {
  // A console line is short; a remote node's megabyte is refused before anything parses it.
  constexpr std::size_t kMaxLineBytes = 1000;
  commands_received_.fetch_add(1, std::memory_order_relaxed);
  const char* data = static_cast<const std_msgs_msg_dds__String_*>(string_message)->data;
  const std::string line =
      data != nullptr ? std::string(data, strnlen(data, kMaxLineBytes + 1)) : std::string();
  if (line.size() > kMaxLineBytes) {
    refuse("/cambio/command: a line longer than " + std::to_string(kMaxLineBytes) + " bytes");
    return;
  }
  if (!command_handler_) {
    refuse("/cambio/command: this run takes no console commands");
    return;
  }
  const std::string refusal = command_handler_(line);
  if (!refusal.empty()) refuse("/cambio/command: " + refusal);
}

void Ros2Bridge::handle_look_at(const void* point_stamped) {
  commands_received_.fetch_add(1, std::memory_order_relaxed);
  const auto& message = *static_cast<const geometry_msgs_msg_dds__PointStamped_*>(point_stamped);
  const std::string frame = message.header.frame_id != nullptr ? message.header.frame_id : "";
  const Eigen::Vector3d p_F_m(message.point.x, message.point.y, message.point.z);
  if (frame.empty()) {
    refuse(
        "/cambio/look_at: header.frame_id is empty; name the tf frame the point is in "
        "(e.g. base)");
    return;
  }
  // A sample can fail while a loop is writing its channel (the reader never waits on a writer);
  // this thread is not a loop's, so it tries again for a few milliseconds before saying no.
  bool sampled = false;
  for (int attempt = 0; attempt < 20 && !(sampled = sources_.joint_states(command_sample_));
       ++attempt) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (!sampled) {
    refuse("/cambio/look_at: no joint state yet to place frame '" + frame + "'");
    return;
  }
  const std::optional<Eigen::Isometry3d> X_BF =
      pose_in_base(sources_.tf_tree, frame, command_sample_.position_rad);
  if (!X_BF) {
    refuse("/cambio/look_at: frame '" + frame + "' is not in this robot's tf tree");
    return;
  }
  const std::string refusal = sources_.look_at(*X_BF * p_F_m);
  if (!refusal.empty()) refuse("/cambio/look_at: " + refusal);
}

void Ros2Bridge::refuse(const std::string& reason) {
  commands_refused_.fetch_add(1, std::memory_order_relaxed);
  std::cerr << "cambio: ROS 2 command refused: " << reason << "\n";
  const std_msgs_msg_dds__String_ message{const_cast<char*>(reason.c_str())};
  write(dds_->refusals, &message, nullptr);  // Counted as refused above.
}

}  // namespace cambio::ros2
