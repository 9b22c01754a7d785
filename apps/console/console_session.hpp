#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "cambio/control/believed_joints.hpp"
#include "console_line.hpp"
#include "main_job.hpp"
#include "robot_actions.hpp"

namespace cambio::app {

/// What the console does with one line, against a main job whose loops are idle while it runs
/// (between the lockstep executor's steps, or beside the realtime executor's threads: it only
/// touches channels). A bad line or a refused action prints why and changes nothing; no line
/// stops the robot except `quit`.
class ConsoleSession {
 public:
  /// What the run loop does next.
  struct Next {
    bool quit = false;
    double wait_s = 0.0;  ///< Advance this much run time before the next line (0: none).
    /// The line sent a command: the loops must run a cycle before the next line, or a second
    /// command on the same (latest-value) channel would replace it unseen.
    bool sent = false;
  };

  /// `scene_objects`: the names `look object NAME` accepts (the simulator's scene).
  ConsoleSession(MainJob& job, RobotActions& actions, std::vector<std::string> scene_objects,
                 std::ostream& out);

  /// Parses and carries out one line; `now_ns` is the run's clock. Never throws for a bad line.
  Next execute(const std::string& line, std::int64_t now_ns);

  /// Takes the stereo pair's images for `capture` (before the run; the remote session does
  /// not: a remote node may not write files on the robot's computer).
  void enable_capture() { images_ = job_.claim_observed_stereo_frames(); }

  std::uint64_t lines_refused() const { return lines_refused_; }
  /// Prints (and counts as refused lines) what the gaze loop and the arms refused since last
  /// asked: the console calls it once a command has had a control period to take effect, so a
  /// refusal follows its line, the last line's too.
  void report_loop_refusals();

 private:
  Next carry_out(const console::Command& command, std::int64_t now_ns);
  void report(const behaviour::ActionResult& result, const std::string& done);
  bool sent_ = false;  // Set by report() for the line being carried out.
  /// The target of look/saccade as the gaze loop takes it; false (and says why) if none.
  bool aim(const console::Target& target, bool saccade);
  void print_status(std::int64_t now_ns);
  void print_ssm(const std::string& save_directory);
  /// The `capture` line (console_session_capture.cpp).
  void capture(const std::string& camera, const std::string& directory, std::int64_t now_ns);

  MainJob& job_;
  RobotActions& actions_;
  std::vector<std::string> scene_objects_;
  std::ostream& out_;
  control::BelievedJoints believed_;
  std::vector<double> q_believed_rig_;
  std::uint64_t lines_refused_ = 0;
  bool features_requested_ = false;
  std::uint64_t gaze_rejections_seen_ = 0;
  std::uint64_t arm_commands_seen_ = 0;
  std::uint64_t homes_refused_seen_ = 0;
  hal::TripleBuffer<hal::StereoFrame>* images_ = nullptr;  // For capture; null: none.
};

}  // namespace cambio::app
