#include "console_session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <opencv2/core.hpp>

#include "cambio/config/echoed_text.hpp"
#include "cambio/config/map_reader.hpp"
#include "feature_map_image.hpp"
#include "image_files.hpp"
#include "output_directory.hpp"
#include "run_trace.hpp"

namespace cambio::app {
namespace {

std::string format(const char* pattern, auto... values) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, values...);
  return text;
}

double degrees(double rad) {
  return rad * 180.0 / std::numbers::pi;
}

control::ArmSide arm_side(console::Arm arm) {
  switch (arm) {
    case console::Arm::kLeft:
      return control::ArmSide::kLeft;
    case console::Arm::kRight:
      return control::ArmSide::kRight;
    case console::Arm::kNearest:
      break;
  }
  return control::ArmSide::kNearest;
}

}  // namespace

ConsoleSession::ConsoleSession(MainJob& job, RobotActions& actions,
                               std::vector<std::string> scene_objects, std::ostream& out)
    : job_(job),
      actions_(actions),
      scene_objects_(std::move(scene_objects)),
      out_(out),
      believed_(job.make_believed_joints()),
      q_believed_rig_(job.joint_order().size(), 0.0) {}

void ConsoleSession::report_loop_refusals() {
  // What the gaze loop refused (it checks what the console cannot: a target behind the eye, a
  // saccade the joints cannot make, a joint that is not the head's).
  if (const control::GazeLoop* gaze_loop = job_.gaze_loop()) {
    const std::uint64_t rejected = gaze_loop->rejected_commands();
    control::GazeStatus status;
    if (rejected > gaze_rejections_seen_ && gaze_loop->status().read(status)) {
      out_ << "refused by the gaze loop: " << rejected - gaze_rejections_seen_
           << " command(s), the last: " << control::to_string(status.last_refusal) << "\n";
      lines_refused_ += rejected - gaze_rejections_seen_;
    }
    gaze_rejections_seen_ = rejected;
  }
  if (const auto* arm_status = job_.arm_status()) {
    control::ArmStatus arms;
    if (arm_status->read(arms) && arms.commands_applied != arm_commands_seen_) {
      arm_commands_seen_ = arms.commands_applied;
      const bool refused = arms.arms[0].phase == control::ReachPhase::kRefused ||
                           arms.arms[1].phase == control::ReachPhase::kRefused;
      if (refused) {
        out_ << "refused by the arms: " << arms.refusal() << "\n";
        ++lines_refused_;
      }
    }
  }
}

ConsoleSession::Next ConsoleSession::execute(const std::string& line, std::int64_t now_ns) {
  report_loop_refusals();  // Any not yet said (the console reports them once its command ran).
  const auto parsed = console::parse(line);
  if (!parsed) return {};
  if (const auto* error = std::get_if<console::ParseError>(&*parsed)) {
    ++lines_refused_;
    out_ << "error: " << error->message << "\n";
    return {};
  }
  sent_ = false;
  Next next = carry_out(std::get<console::Command>(*parsed), now_ns);
  next.sent = sent_;
  return next;
}

void ConsoleSession::report(const behaviour::ActionResult& result, const std::string& done) {
  if (!result.sent) {
    ++lines_refused_;
    out_ << "refused: " << result.message << "\n";
    return;
  }
  sent_ = true;
  if (!result.message.empty()) out_ << "clamped: " << result.message << "\n";
  out_ << done << "\n";
}

bool ConsoleSession::aim(const console::Target& target, bool saccade) {
  const auto& v = target.values;
  switch (target.kind) {
    case console::TargetKind::kPixel:
      report(saccade ? actions_.saccade_to_pixel(v[0], v[1]) : actions_.look_at_pixel(v[0], v[1]),
             format("%s pixel (%.1f, %.1f)", saccade ? "saccade to" : "fixating", v[0], v[1]));
      return true;
    case console::TargetKind::kPoint: {
      const Eigen::Vector3d p(v[0], v[1], v[2]);
      report(saccade ? actions_.saccade_to_point(p) : actions_.look_at_point(p),
             format("%s point (%.3f, %.3f, %.3f) m", saccade ? "saccade to" : "fixating", v[0],
                    v[1], v[2]));
      return true;
    }
    case console::TargetKind::kAngles:
      // The gaze loop takes angular displacements as saccades; fixating them is the same jump.
      report(actions_.saccade_by_angles(v[0], v[1]),
             format("saccade by pan %.2f deg, tilt %.2f deg", degrees(v[0]), degrees(v[1])));
      return true;
    case console::TargetKind::kObject: {
      sim::GroundTruth* truth = job_.ground_truth();
      if (std::find(scene_objects_.begin(), scene_objects_.end(), target.object) ==
              scene_objects_.end() ||
          truth == nullptr) {
        ++lines_refused_;
        std::string why = "refused: no scene object " + config::in_quotes(target.object);
        if (const auto near = config::closest_name(target.object, scene_objects_)) {
          why += "; did you mean " + config::in_quotes(*near) + "?";
        } else if (!scene_objects_.empty()) {
          why += " (objects:";
          for (const auto& name : scene_objects_) why += " " + name;
          why += ")";
        }
        out_ << why << "\n";
        return false;
      }
      // A convenience of the simulator: the object's true centre, given as a point.
      const Eigen::Vector3d p = truth->X_WO(target.object).translation();
      report(saccade ? actions_.saccade_to_point(p) : actions_.look_at_point(p),
             format("%s %s at (%.3f, %.3f, %.3f) m", saccade ? "saccade to" : "fixating",
                    target.object.c_str(), p.x(), p.y(), p.z()));
      return true;
    }
  }
  return false;
}

ConsoleSession::Next ConsoleSession::carry_out(const console::Command& command,
                                               std::int64_t now_ns) {
  using namespace console;
  Next next;
  std::visit(
      [&](const auto& c) {
        using T = std::decay_t<decltype(c)>;
        if constexpr (std::is_same_v<T, Help>) {
          for (const std::string& text : help_lines()) {
            if (c.topic.empty() || text.rfind(c.topic + " ", 0) == 0 || text.rfind(c.topic, 0) == 0)
              out_ << text << "\n";
          }
        } else if constexpr (std::is_same_v<T, Quit>) {
          next.quit = true;
        } else if constexpr (std::is_same_v<T, Status>) {
          print_status(now_ns);
        } else if constexpr (std::is_same_v<T, Wait>) {
          next.wait_s = c.seconds;
        } else if constexpr (std::is_same_v<T, MoveJoint>) {
          // Say where it goes: the angle asked, within the joint's limits (one truth with the
          // clamp note).
          double to_rad = c.angle_rad;
          if (const hal::JointInfo* joint = job_.hardware().find_joint(c.joint)) {
            to_rad =
                std::clamp(to_rad, joint->limits.min_position_rad, joint->limits.max_position_rad);
          }
          report(actions_.move_joint(c.joint, c.angle_rad),
                 format("moving %s to %.2f deg", c.joint.c_str(), degrees(to_rad)));
        } else if constexpr (std::is_same_v<T, Look>) {
          aim(c.target, false);
        } else if constexpr (std::is_same_v<T, Saccade>) {
          aim(c.target, true);
        } else if constexpr (std::is_same_v<T, Pursue>) {
          report(actions_.pursue(), "pursuing what the dominant eye fixates");
        } else if constexpr (std::is_same_v<T, Hold>) {
          report(actions_.hold(), "holding the head");
        } else if constexpr (std::is_same_v<T, Verge>) {
          report(actions_.verge(c.on), c.on ? "vergence on" : "vergence off");
        } else if constexpr (std::is_same_v<T, Reach>) {
          const control::ArmSide arm = arm_side(c.arm);
          if (c.fixation) {
            report(actions_.reach_fixated(arm), "reaching what the head fixates");
          } else {
            const Eigen::Vector3d p(c.point[0], c.point[1], c.point[2]);
            report(actions_.reach_point(p, arm),
                   format("reaching (%.3f, %.3f, %.3f) m", p.x(), p.y(), p.z()));
          }
        } else if constexpr (std::is_same_v<T, Gripper>) {
          const control::ArmSide arm = arm_side(c.arm);
          report(c.close ? actions_.grasp(arm) : actions_.release(arm),
                 c.close ? "closing the gripper" : "opening the gripper");
        } else if constexpr (std::is_same_v<T, Ssm>) {
          print_ssm(c.save_directory);
        }
      },
      command);
  return next;
}

void ConsoleSession::print_status(std::int64_t now_ns) {
  out_ << format("t %.3f s\n", static_cast<double>(now_ns) * 1e-9);
  if (const control::GazeLoop* gaze_loop = job_.gaze_loop()) {
    control::GazeStatus gaze;
    if (gaze_loop->status().read(gaze) && gaze.stamp_ns > 0) {
      out_ << format(
          "gaze: %s%s, vergence %.2f deg, disparity %s, image error %.1f px, rejected %llu\n",
          gaze_action_name(gaze.action), gaze.saccade_active ? " (saccade under way)" : "",
          degrees(gaze.vergence_rad),
          gaze.disparity_valid
              ? format("%.2f px (confidence %.2f)", gaze.disparity_px, gaze.disparity_confidence)
                    .c_str()
              : "invalid",
          gaze.feature_error_px, static_cast<unsigned long long>(gaze_loop->rejected_commands()));
      if (gaze.believed_fixation_valid) {
        const auto& p = gaze.believed_fixation_W_m;
        out_ << format("believed fixation (stereo): (%.3f, %.3f, %.3f) m\n", p[0], p[1], p[2]);
      } else {
        out_ << "believed fixation (stereo): none (the eyes' axes do not meet)\n";
      }
    }
  }
  if (const auto* arm_status = job_.arm_status()) {
    control::ArmStatus arms;
    if (arm_status->read(arms) && arms.stamp_ns > 0) {
      for (int side = 0; side < 2; ++side) {
        const control::ArmStatus::Arm& arm = arms.arms[static_cast<std::size_t>(side)];
        const auto& g = arm.gripper_W_m;
        out_ << format("%s arm: %s, gripper %s at (%.3f, %.3f, %.3f) m",
                       side == 0 ? "left" : "right", reach_phase_name(arm.phase),
                       arm.gripper_closed ? "closed" : "open", g[0], g[1], g[2]);
        if (arm.phase == control::ReachPhase::kReaching ||
            arm.phase == control::ReachPhase::kTouching ||
            arm.phase == control::ReachPhase::kArrived) {
          out_ << format(", %.3f m from its target", arm.distance_to_target_m);
        }
        out_ << "\n";
      }
    }
  }
  const bool reported = believed_.read(q_believed_rig_);
  sim::GroundTruth* truth = job_.ground_truth();
  out_ << format("%-22s %12s %12s\n", "joint", "believed", truth != nullptr ? "true" : "");
  for (std::size_t i = 0; i < q_believed_rig_.size(); ++i) {
    const std::string& name = job_.joint_order()[i];
    std::string true_text;
    if (truth != nullptr) true_text = format("%8.3f deg", degrees(truth->joint_position_rad(name)));
    out_ << format("%-22s %8.3f deg %12s\n", name.c_str(), degrees(q_believed_rig_[i]),
                   true_text.c_str());
  }
  if (!reported) out_ << "(some joints have not reported yet)\n";
  if (believed_.holding()) out_ << "a joint loop HOLDS: a fault is latched or feedback is stale\n";
}

void ConsoleSession::print_ssm(const std::string& save_directory) {
  perception::SsmServer* ssm = job_.perception();
  if (ssm == nullptr) {
    ++lines_refused_;
    out_ << "refused: this rig has no stereo pair, so no SSM\n";
    return;
  }
  if (!features_requested_) {
    // Everything the SSM computes, from its next frame on (the gaze alone asks for disparity,
    // and motion while pursuing).
    const behaviour::ActionResult asked = actions_.request_features(perception::FeatureRequest{});
    features_requested_ = asked.sent;
    if (asked.sent) {
      out_ << "ssm: every feature (motion, moments, all maps) requested from now on\n";
    }
  }
  perception::SsmSummary s;
  if (!ssm->summaries().read(s) || s.sequence == 0) {
    out_ << "ssm: no frame processed yet (wait a little)\n";
    return;
  }
  const auto& d = s.disparity;
  out_ << format("ssm frame %llu at %.3f s: %d levels, %.0f us\n",
                 static_cast<unsigned long long>(s.sequence),
                 static_cast<double>(s.stamp_ns) * 1e-9, s.levels, s.timings.total_us);
  out_ << (d.valid ? format("  disparity %.2f px (confidence %.2f, level %d)\n",
                            static_cast<double>(d.disparity_px), static_cast<double>(d.confidence),
                            d.level)
                   : std::string("  disparity invalid (no texture or no match)\n"));
  for (int eye = 0; eye < 2; ++eye) {
    const auto e = static_cast<std::size_t>(eye);
    const auto& m = s.motion[e];
    const auto& moments = s.moments[e][0];
    out_ << format("  %s eye: fixation (%d, %d) px; motion %s; moments L0 %s\n",
                   eye == 0 ? "left" : "right", s.fixation[e].x, s.fixation[e].y,
                   m.valid ? format("(%.2f, %.2f) px/frame", static_cast<double>(m.flow_x_px),
                                    static_cast<double>(m.flow_y_px))
                                 .c_str()
                           : "none",
                   moments.valid
                       ? format("area %.0f px2, centroid (%.1f, %.1f) px", moments.area_px2,
                                moments.centroid_x_px, moments.centroid_y_px)
                             .c_str()
                       : "empty");
  }
  if (save_directory.empty()) return;

  // The maps: the loops are idle, so this thread may read the SSM's frame buffer.
  const perception::SensoryServo* servo = ssm->servo();
  auto& frames = ssm->frames();
  frames.acquire();
  const perception::SsmFrame& frame = frames.front();
  if (servo == nullptr || frame.summary.sequence == 0) {
    out_ << "ssm: no maps yet\n";
    return;
  }
  try {
    OutputDirectory out(save_directory, "console");
    const int w = servo->config().retina.width_px;
    const int h = servo->config().retina.height_px;
    const auto& specs = servo->operators().maps();
    for (int eye = 0; eye < 2; ++eye) {
      for (int k = 0; k < frame.summary.levels; ++k) {
        for (std::size_t i = 0; i < specs.size(); ++i) {
          const bool signed_map = is_signed_map(specs[i]);
          const cv::Mat tile = feature_map_tile(
              frame.maps[static_cast<std::size_t>(eye)].map(k, static_cast<int>(i)), w, h,
              signed_map, w, h);
          hal::Image png(w, h, hal::PixelFormat::kGrey8);
          std::copy(tile.datastart, tile.dataend, png.pixels.begin());
          out.stage(format("%s_L%d_%s.png", eye == 0 ? "left" : "right", k, specs[i].name.c_str()),
                    encode_png(png));
        }
      }
    }
    out.commit();
    out_ << "ssm: wrote " << out.files().size() << " maps of frame " << frame.summary.sequence
         << " to " << out.path().string() << "\n";
  } catch (const std::exception& error) {
    ++lines_refused_;
    out_ << "refused: ssm save: " << error.what() << "\n";
  }
}

}  // namespace cambio::app
