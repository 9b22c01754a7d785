#pragma once

#include <cstdint>
#include <vector>

struct mjModel_;
struct mjData_;

namespace cambio::sim {

/// The part of the true world state that determines what is seen: joint and free-body positions
/// and the scripted (mocap) poses. The physics loop publishes one per step through a
/// TripleBuffer; renderers and ground truth read it on their own threads.
struct WorldSnapshot {
  std::int64_t stamp_ns = 0;  ///< Sim clock time of the step that produced it.
  std::uint64_t step = 0;     ///< Physics steps taken so far; 0 = the initial state.
  double time_s = 0.0;        ///< MuJoCo's time (s since reset).
  std::vector<double> qpos;
  std::vector<double> qvel;
  std::vector<double> mocap_pos;
  std::vector<double> mocap_quat;

  /// Sizes the vectors for a model. Allocates; call at configure time.
  void resize_for(const mjModel_* model);
  /// Copies the state of `data`. Real-time safe (sizes already match).
  void capture(const mjModel_* model, const mjData_* data, std::int64_t stamp,
               std::uint64_t steps) noexcept;
  /// Writes the state into `data` (qpos, qvel, mocap, time); forward kinematics is the
  /// caller's. Real-time safe.
  void restore(const mjModel_* model, mjData_* data) const noexcept;
};

}  // namespace cambio::sim
