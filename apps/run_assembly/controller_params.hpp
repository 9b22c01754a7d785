#pragma once

#include "cambio/config/experiment_config.hpp"
#include "cambio/config/rig_config.hpp"
#include "cambio/control/arm_reach_loop.hpp"
#include "cambio/control/command_script.hpp"
#include "cambio/control/gaze_loop.hpp"
#include "cambio/control/joint_loop.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/runtime/scheduled_loop.hpp"

namespace cambio::app {

/// The one place where experiment and rig settings become the parameters of the runtime and the
/// controllers (control/ and the runtime never read configuration themselves).

/// A configured loop's schedule for the executors.
runtime::LoopSchedule schedule_of(const config::LoopConfig& loop);

/// A rig loop's schedule for the executors. Throws std::runtime_error if the rig has no loop of
/// that name.
runtime::LoopSchedule loop_schedule(const config::RigConfig& rig, const std::string& loop_name);

/// The joint loop's watchdogs from the rig's `loops.joint`.
control::JointLoopParams joint_loop_params(const config::RigConfig& rig);

/// Each joint's `max_tracking_error` from the rig, in hardware.joints order (the controllers'
/// CommandTracking limits). Throws std::runtime_error for a joint the rig does not describe.
std::vector<double> max_tracking_errors_rad(const config::RigConfig& rig,
                                            const hal::HardwareInfo& hardware);

/// The gaze loop of a `task: gaze` experiment: its `gaze:` settings, the verging camera's focal
/// length, the joints' tracking limits. Throws std::runtime_error if the rig has no stereo pair.
control::GazeLoopParams gaze_loop_params(const config::ExperimentConfig& experiment,
                                         const hal::HardwareInfo& hardware);

/// The arm loop of a `task: gaze` experiment on a rig with arms: its `arm:` settings, the arms'
/// groups ([0] left, [1] right; "" for none), the joints' tracking limits. The fingers come with
/// each arm's chain.
control::ArmReachParams arm_reach_params(const config::ExperimentConfig& experiment,
                                         const hal::HardwareInfo& hardware,
                                         std::array<std::string, 2> groups);

/// The config's name for a gaze action as the gaze loop's (the same enumerators).
control::GazeAction gaze_action(config::GazeAction action);

/// The experiment's `commands:` as the command script's timeline.
std::vector<control::CommandScript::Entry> command_script(
    const config::ExperimentConfig& experiment);

}  // namespace cambio::app
