#pragma once

// INTERIM, to be replaced by control::RobotActions (the concrete Actions another change brings:
// HardwareInfo, the gaze command channel, an optional arm command channel). Until it lands this
// turns a behaviour's gaze actions into GazeCommands and refuses the rest, so MainJob's
// behaviour wiring can be written and tested against the abstract behaviour::Actions. It checks
// nothing the gaze loop checks itself (targets, joint limits): the gaze loop rejects and counts.

#include <cstdint>

#include "cambio/behaviour/behaviour.hpp"
#include "cambio/control/gaze_command.hpp"
#include "cambio/hal/seqlock_channel.hpp"

namespace cambio::app {

class InterimGazeActions final : public behaviour::Actions {
 public:
  /// `commands`: the gaze loop's command channel; this becomes its one writer.
  explicit InterimGazeActions(hal::SeqlockChannel<control::GazeCommand>& commands)
      : commands_(commands) {}

  behaviour::ActionResult look_at_pixel(double u_px, double v_px) override;
  behaviour::ActionResult look_at_point(const Eigen::Vector3d& p_W_m) override;
  behaviour::ActionResult saccade_to_pixel(double u_px, double v_px) override;
  behaviour::ActionResult saccade_to_point(const Eigen::Vector3d& p_W_m) override;
  behaviour::ActionResult saccade_by_angles(double pan_rad, double tilt_rad) override;
  behaviour::ActionResult pursue() override;
  behaviour::ActionResult hold() override;
  /// Applies from the next gaze command on.
  behaviour::ActionResult verge(bool on) override;
  behaviour::ActionResult reach_fixated(control::ArmSide arm) override;
  behaviour::ActionResult reach_point(const Eigen::Vector3d& p_W_m, control::ArmSide arm) override;
  behaviour::ActionResult grasp(control::ArmSide arm) override;
  behaviour::ActionResult release(control::ArmSide arm) override;
  behaviour::ActionResult move_joint(std::string_view joint_name, double position_rad) override;

 private:
  behaviour::ActionResult send(control::GazeAction action, const control::GazeTarget& target);

  hal::SeqlockChannel<control::GazeCommand>& commands_;
  std::uint64_t sequence_ = 0;
  bool verge_ = true;
};

}  // namespace cambio::app
