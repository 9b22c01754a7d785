#include "console_session.hpp"

#include <algorithm>

#include "cambio/config/echoed_text.hpp"
#include "console_session_detail.hpp"

namespace cambio::app {
namespace {

using console::detail::degrees;
using console::detail::format;

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
  // A joint whose drive does not home (an absolute encoder, the sim) refuses `home`.
  if (const std::uint64_t refused = job_.homes_refused(); refused > homes_refused_seen_) {
    out_ << "refused: joint " << config::in_quotes(job_.last_refused_home())
         << " does not home (its rig entry sets no homing, or its backend has none)\n";
    lines_refused_ += refused - homes_refused_seen_;
    homes_refused_seen_ = refused;
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

ConsoleSession::Next ConsoleSession::carry_out(const console::Command& command,
                                               std::int64_t now_ns) {
  using namespace console;
  Next next;
  std::visit(
      [&](const auto& c) {
        using T = std::decay_t<decltype(c)>;
        if constexpr (std::is_same_v<T, Help>) {
          // The parser has checked that a topic names a command.
          for (const std::string& text : help_lines()) {
            if (c.topic.empty() || text.rfind(c.topic + " ", 0) == 0 || text == c.topic ||
                text.rfind(c.topic + "\n", 0) == 0)
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
        } else if constexpr (std::is_same_v<T, Home>) {
          if (!job_.request_home(c.joint)) {
            ++lines_refused_;
            out_ << "refused: " << config::in_quotes(c.joint) << " is not a joint of the rig\n";
          } else {
            sent_ = true;
            out_ << (c.joint.empty() ? std::string("homing every joint that lost its reference")
                                     : "homing " + c.joint)
                 << "\n";
          }
        } else if constexpr (std::is_same_v<T, Ssm>) {
          print_ssm(c.save_directory);
        } else if constexpr (std::is_same_v<T, Capture>) {
          capture(c.camera, c.directory, now_ns);
        }
      },
      command);
  return next;
}

}  // namespace cambio::app
