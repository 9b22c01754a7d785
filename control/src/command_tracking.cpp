#include "cambio/control/command_tracking.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

namespace cambio::control {

CommandTracking::CommandTracking(std::string controller, std::vector<Joint> joints)
    : controller_(std::move(controller)), joints_(std::move(joints)), bounded_(joints_.size(), 1) {
  for (const Joint& joint : joints_) {
    if (!(joint.max_error_rad > 0.0)) {
      throw std::invalid_argument(controller_ + ": the tracking error limit of '" + joint.name +
                                  "' must be > 0 rad");
    }
    if (joint.rig < 0 || joint.index < 0) {
      throw std::invalid_argument(controller_ + ": a negative joint index for '" + joint.name +
                                  "'");
    }
  }
}

CommandTracking::Step CommandTracking::step(const BelievedJoints& believed) noexcept {
  if (faulted_) return Step::kFaulted;
  bool follows = !believed.holding();
  for (const Joint& joint : joints_) {
    follows = follows && joint.rig < believed.rig_joint_count() && believed.driven(joint.rig);
  }
  if (!follows) {
    if (!frozen_) {
      frozen_run_cycles_ = 0;
      drive_lost_ = false;
    }
    frozen_ = true;
    ++frozen_run_cycles_;
    ++frozen_cycles_;
    for (const Joint& joint : joints_) {
      drive_lost_ =
          drive_lost_ || joint.rig >= believed.rig_joint_count() || !believed.enabled(joint.rig);
    }
    return Step::kFrozen;
  }
  if (frozen_) {
    frozen_ = false;
    // A brief hold (a late answer on a loaded bus) with every drive still enabled left the joints
    // where the command had them going: resuming keeps the servo's lead, which restarting from the
    // measured pose would throw away at every such hold (the gaze then never converges).
    if (drive_lost_ || frozen_run_cycles_ > kBriefHoldCycles) {
      ++restarts_;
      return Step::kRestart;
    }
  }
  return Step::kFollow;
}

void CommandTracking::restart(std::span<double> q_command,
                              std::span<const double> q_measured) noexcept {
  for (const Joint& joint : joints_) {
    const auto i = static_cast<std::size_t>(joint.index);
    if (i < q_command.size() && i < q_measured.size()) q_command[i] = q_measured[i];
  }
}

bool CommandTracking::check(std::span<const double> q_command,
                            std::span<const double> q_measured) noexcept {
  if (faulted_) return false;
  for (std::size_t k = 0; k < joints_.size(); ++k) {
    const Joint& joint = joints_[k];
    const auto i = static_cast<std::size_t>(joint.index);
    if (i >= q_command.size() || i >= q_measured.size() || bounded_[k] == 0) continue;
    const double error_rad = std::abs(q_command[i] - q_measured[i]);
    if (error_rad > peak_error_rad_) {
      peak_error_rad_ = error_rad;
      peak_joint_ = static_cast<int>(k);
    }
    // NaN-proof: a command or measurement that is not a number is beyond every limit.
    if (!(error_rad <= joint.max_error_rad)) {
      faulted_ = true;
      std::snprintf(message_.data(), message_.size(),
                    "%s: tracking error: %s is %.3f rad (%.1f deg) from its command, beyond its "
                    "max_tracking_error of %.3f rad: the joint does not follow",
                    controller_.c_str(), joint.name.c_str(), error_rad,
                    error_rad * 180.0 / std::numbers::pi, joint.max_error_rad);
      return true;
    }
  }
  return false;
}

void CommandTracking::set_bounded(std::size_t joint, bool bounded) noexcept {
  if (joint < bounded_.size()) bounded_[joint] = bounded ? 1 : 0;
}

TrackingReport CommandTracking::report() const {
  TrackingReport report;
  report.controller = controller_;
  report.frozen_cycles = frozen_cycles_;
  report.restarts = restarts_;
  report.peak_error_rad = peak_error_rad_;
  if (peak_joint_ >= 0) {
    const Joint& joint = joints_[static_cast<std::size_t>(peak_joint_)];
    report.peak_joint = joint.name;
    report.peak_joint_limit_rad = joint.max_error_rad;
  }
  report.faulted = faulted_;
  report.fault = std::string(fault_message());
  return report;
}

}  // namespace cambio::control
