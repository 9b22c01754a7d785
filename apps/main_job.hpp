#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cambio/config/experiment_config.hpp"
#include "cambio/control/joint_loop.hpp"
#include "cambio/control/vergence_loop.hpp"
#include "cambio/hal/backend_factory.hpp"
#include "cambio/perception/ssm_server.hpp"
#include "cambio/runtime/loop_statistics.hpp"
#include "camera_loop.hpp"
#include "latest_frame_camera.hpp"

namespace cambio::app {

/// What a run produced, for the report and --out.
struct MainJobResult {
  std::vector<runtime::LoopStatistics> loops;
  std::uint64_t camera_frames = 0;
  std::uint64_t watchdog_cycles = 0;
  bool stopped_by_signal = false;
  double simulated_s = 0.0;
  double wall_s = 0.0;
  std::optional<perception::SsmSummary> perception;  ///< The newest, if perception ran.
  std::optional<control::VergenceStatus> vergence;   ///< If the task was vergence.
};

/// The main job: the rig's backends built through the factory, and the loops wired through
/// latest-value channels:
///   camera loop -> (per camera) -> perception loop (SSM) -> control loop -> joint loop -> backends
/// plus the backends' own loops (the sim's physics). Construction builds and configures
/// everything (throws on any problem); run() only runs.
class MainJob {
 public:
  MainJob(const config::ExperimentConfig& experiment, const hal::BackendFactory& factory);
  ~MainJob();

  /// Runs for the experiment's duration or until `stop`; `progress(done_s, wall_s)` is called
  /// about every 0.1 s of run time.
  MainJobResult run(const std::atomic<bool>& stop,
                    const std::function<void(double, double)>& progress);

  /// The newest frame of each camera (rig order), for --out, after run(); sequence 0 if none
  /// arrived.
  std::vector<const hal::Image*> last_frames();
  const std::vector<config::CameraConfig>& cameras() const { return experiment_.rig.cameras; }

 private:
  void build_backends(const hal::BackendFactory& factory);
  void build_loops();
  int joint_index(const std::string& joint_name) const;

  config::ExperimentConfig experiment_;
  std::map<std::string, std::unique_ptr<hal::Backend>> backends_;
  std::vector<std::unique_ptr<hal::JointGroup>> groups_;
  std::vector<std::unique_ptr<hal::Camera>> cameras_;
  std::vector<std::string> joint_order_;  // Rig order: the groups' joint lists concatenated.

  hal::SeqlockChannel<control::JointTargetFrame> targets_;
  hal::SeqlockChannel<control::JointStateFrame> states_;
  std::unique_ptr<control::JointLoop> joint_loop_;
  std::unique_ptr<hal::Loop> control_loop_;
  control::VergenceLoop* vergence_loop_ = nullptr;  // control_loop_ when the task is vergence.
  std::unique_ptr<CameraLoop> camera_loop_;
  std::vector<std::unique_ptr<LatestFrameCamera>> frame_readers_;
  std::unique_ptr<perception::SsmServer> perception_loop_;
};

}  // namespace cambio::app
